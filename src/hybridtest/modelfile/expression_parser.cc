// The recursive-descent parser of model-file expressions: text to a checked, constant-folded
// node list with dimensions. See expression.h.
#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>

#include "hybridtest/modelfile/expression.h"
#include "hybridtest/modelfile/expression_ops.h"
#include "hybridtest/modelfile/kinematics_mirror.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile {
namespace {
bool IsNameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool IsNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}
}  // namespace

class Parser {
 public:
  Parser(std::string_view text, const SymbolTable& symbols) : text_(text), symbols_(symbols) {}

  Expression Run() {
    Skip();
    if (pos_ >= text_.size()) Fail("", "the expression is empty; write a number or a formula");
    e_.root_ = ParseExpr();
    e_.dim_ = dims_[static_cast<std::size_t>(e_.root_)];
    Skip();
    if (pos_ < text_.size()) {
      Fail(std::string(1, text_[pos_]), "unexpected character after a complete expression; "
                                        "check for a missing operator or parenthesis");
    }
    return std::move(e_);
  }

 private:
  [[noreturn]] void Fail(std::string token, std::string message) const {
    throw ExpressionError{static_cast<int>(token_start_), std::move(token), std::move(message)};
  }
  void Skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    token_start_ = pos_;
  }
  bool Accept(std::string_view s) {
    Skip();
    if (text_.substr(pos_, s.size()) == s) {
      pos_ += s.size();
      return true;
    }
    return false;
  }
  // Guards the recursion of the parser itself (parentheses, unary signs, calls).
  struct DepthGuard {
    explicit DepthGuard(Parser& p) : parser(p) {
      if (++parser.recursion_ > kMaxExpressionDepth) parser.FailDepth();
    }
    ~DepthGuard() { --parser.recursion_; }
    Parser& parser;
  };
  [[noreturn]] void FailDepth() {
    Fail(std::string(text_.substr(token_start_, 1)),
         fmt::format("the expression nests deeper than {} levels (parentheses, function calls or "
                     "a chain of operators); split it into parameters or time functions",
                     kMaxExpressionDepth));
  }
  // The dimension of an operation from its operands' (dimensions.cc); fails on a mismatch at
  // token_start_ (the operator or the function's name).
  Dim NodeDim(const Node& n) {
    const Dim none;
    auto dim_of = [&](int k) { return k >= 0 ? dims_[static_cast<std::size_t>(k)] : none; };
    const bool constant_b = n.b >= 0 && e_.nodes_[static_cast<std::size_t>(n.b)].op == Op::kConst;
    std::string error;
    const Dim d = CombineDims(n.op, dim_of(n.a), dim_of(n.b), dim_of(n.c), constant_b,
                              constant_b ? e_.nodes_[static_cast<std::size_t>(n.b)].value : 0.0,
                              &error);
    if (!error.empty()) {
      std::size_t end = token_start_;
      while (end < text_.size() && IsNameChar(text_[end])) ++end;
      Fail(std::string(text_.substr(token_start_, std::max<std::size_t>(1, end - token_start_))),
           error);
    }
    return d;
  }
  // Appends a node (with `leaf`, the dimension of a node without operands) and returns its
  // index.
  int Push(Node n, Dim leaf = {}) {
    // Constant folding: operations on constants become constants; an `if` with a constant
    // condition becomes its branch.
    if (n.op == Op::kIf && e_.nodes_[n.a].op == Op::kConst) {
      return e_.nodes_[n.a].value != 0.0 ? n.b : n.c;
    }
    const Dim dim = n.a >= 0 ? NodeDim(n) : leaf;
    const bool ca = n.a >= 0 && e_.nodes_[n.a].op == Op::kConst;
    const bool cb = n.b < 0 || e_.nodes_[n.b].op == Op::kConst;
    if (n.op != Op::kConst && n.op != Op::kIf && n.a >= 0 && ca && cb) {
      const double b = n.b >= 0 ? e_.nodes_[n.b].value : 0.0;
      n = Node{Op::kConst, Fold(n.op, e_.nodes_[n.a].value, b), -1, -1, -1, -1};
    }
    int depth = 1;
    for (int child : {n.a, n.b, n.c}) {
      if (child >= 0) depth = std::max(depth, depth_[static_cast<std::size_t>(child)] + 1);
    }
    if (depth > kMaxExpressionDepth) FailDepth();
    e_.nodes_.push_back(n);
    depth_.push_back(depth);
    dims_.push_back(dim);
    return static_cast<int>(e_.nodes_.size()) - 1;
  }
  // The condition of an `if`: two expressions compared.
  int ParseCondition() {
    const int left = ParseExpr();
    Skip();
    Op op;
    if (Accept("<=")) {
      op = Op::kLe;
    } else if (Accept(">=")) {
      op = Op::kGe;
    } else if (Accept("<")) {
      op = Op::kLt;
    } else if (Accept(">")) {
      op = Op::kGt;
    } else if (text_.substr(pos_, 2) == "==" || text_.substr(pos_, 2) == "!=") {
      Fail(std::string(text_.substr(pos_, 2)), "equality of real numbers is fragile and not "
                                               "offered; compare with < <= > >=");
    } else {
      Fail(std::string(text_.substr(token_start_, 1)),
           "the condition of if(cond, a, b) compares two expressions with < <= > >=, e.g. "
           "if(v < 0, a, b)");
    }
    const std::size_t at = token_start_;
    const int right = ParseExpr();
    token_start_ = at;
    return Push({op, 0, -1, left, right, -1});
  }
  // `left` op (the right operand `right()` parses), just after the operator was accepted: a
  // dimension error points at the operator.
  template <class Right>
  int Binary(Op op, int left, const Right& right) {
    const std::size_t at = token_start_;
    const int r = right();
    token_start_ = at;
    return Push({op, 0, -1, left, r, -1});
  }
  int ParseExpr() {
    int left = ParseTerm();
    for (;;) {
      if (Accept("+")) {
        left = Binary(Op::kAdd, left, [&] { return ParseTerm(); });
      } else if (Accept("-")) {
        left = Binary(Op::kSub, left, [&] { return ParseTerm(); });
      } else {
        return left;
      }
    }
  }
  int ParseTerm() {
    int left = ParseUnary();
    for (;;) {
      Skip();
      if (text_.substr(pos_, 2) == "**") return left;
      if (Accept("*")) {
        left = Binary(Op::kMul, left, [&] { return ParseUnary(); });
      } else if (Accept("/")) {
        left = Binary(Op::kDiv, left, [&] { return ParseUnary(); });
      } else {
        return left;
      }
    }
  }
  int ParseUnary() {
    if (Accept("-")) {
      const DepthGuard guard(*this);
      return Push({Op::kNeg, 0, -1, ParseUnary(), -1, -1});
    }
    if (Accept("+")) {
      const DepthGuard guard(*this);
      return ParseUnary();
    }
    return ParsePower();
  }
  int ParsePower() {
    const int base = ParsePrimary();
    if (Accept("**") || Accept("^")) {
      const DepthGuard guard(*this);  // 2^2^2^…: right-associative, so recursive
      return Binary(Op::kPow, base, [&] { return ParseUnary(); });
    }
    return base;
  }
  int ParsePrimary() {
    Skip();
    if (pos_ >= text_.size()) Fail("", "the expression ends early; complete the formula");
    const char c = text_[pos_];
    if (c == '(') {
      const DepthGuard guard(*this);
      ++pos_;
      const int inner = ParseExpr();
      if (!Accept(")")) Fail(std::string(text_.substr(token_start_, 1)), "expected ')'");
      return inner;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return ParseNumber();
    if (IsNameStart(c)) return ParseName();
    Fail(std::string(1, c), "expected a number, a name, a function call or '('");
  }
  int ParseNumber() {
    const std::string rest(text_.substr(pos_));
    char* end = nullptr;
    const double v = std::strtod(rest.c_str(), &end);
    if (end == rest.c_str()) Fail(rest.substr(0, 1), "expected a number");
    pos_ += static_cast<std::size_t>(end - rest.c_str());
    // A unit after the number (`30 deg`, `600 mm`, `8 m/s`, `50 kN·m/rad`): converted to SI
    // here. The unit is the longest run without spaces that is a unit (units.h), else its first
    // word if that is one; `2 m*x` is 2 m times x.
    std::size_t p = pos_;
    while (p < text_.size() && text_[p] == ' ') ++p;
    auto unit_char = [&](std::size_t k) {
      return IsNameChar(text_[k]) || static_cast<unsigned char>(text_[k]) >= 0x80;
    };
    if (p < text_.size() && unit_char(p) && !std::isdigit(static_cast<unsigned char>(text_[p]))) {
      std::size_t word = p;
      while (word < text_.size() && unit_char(word)) ++word;
      std::size_t run = word;
      while (run < text_.size() && (unit_char(run) || text_[run] == '/' || text_[run] == '*' ||
                                    text_[run] == '^' || (text_[run] == '-' && text_[run - 1] == '^'))) {
        ++run;
      }
      std::string why;
      std::optional<Unit> unit;
      std::size_t unit_end = run;
      if (run > word) unit = ParseUnit(text_.substr(p, run - p), &why);
      if (!unit) {
        unit_end = word;
        unit = ParseUnit(text_.substr(p, word - p), &why);
      }
      if (unit) {
        // Each word of the unit must not also be a declared name (`2 m` with a mass m).
        std::size_t k = p;
        while (k < unit_end) {
          std::size_t w = k;
          while (w < unit_end && IsNameChar(text_[w])) ++w;
          if (w > k && symbols_.Find(text_.substr(k, w - k)) != nullptr) {
            token_start_ = k;
            Fail(std::string(text_.substr(k, w - k)),
                 fmt::format("ambiguous: '{0}' is both a unit and a declared name; write `* {0}` "
                             "for the name", text_.substr(k, w - k)));
          }
          k = w == k ? k + 1 : w;
        }
        pos_ = unit_end;
        return Push({Op::kConst, v * unit->to_si, -1, -1, -1, -1}, Dim::FromUnit(unit->dim));
      }
    }
    return Push({Op::kConst, v, -1, -1, -1, -1});
  }
  int ParseName() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && IsNameChar(text_[pos_])) ++pos_;
    const std::string name(text_.substr(start, pos_ - start));
    const std::size_t name_start = start;
    Skip();
    if (pos_ < text_.size() && text_[pos_] == '(' &&
        (name == "velocity" || name == "angular_velocity")) {
      return ParseVelocity(name, name_start);
    }
    if (pos_ < text_.size() && text_[pos_] == '(') {
      for (const FunctionInfo& f : KnownFunctions()) {
        if (name != f.name) continue;
        const DepthGuard guard(*this);
        ++pos_;
        const int a = f.op == Op::kIf ? ParseCondition() : ParseExpr();
        int b = -1, c3 = -1;
        const char* usage = f.op == Op::kIf ? "if(cond, a, b)" : f.arity == 2 ? "(a, b)" : "(a)";
        if (f.arity >= 2) {
          if (!Accept(",")) {
            token_start_ = name_start;
            Fail(name, fmt::format("{}() takes {} arguments: {}{}", name,
                                   f.arity == 2 ? "two" : "three", f.op == Op::kIf ? "" : name,
                                   usage));
          }
          b = ParseExpr();
        }
        if (f.arity == 3) {
          if (!Accept(",")) {
            token_start_ = name_start;
            Fail(name, fmt::format("if() takes three arguments: {}", usage));
          }
          c3 = ParseExpr();
        }
        if (!Accept(")")) {
          token_start_ = name_start;
          Fail(name, fmt::format("{}() takes {} argument{}; close it with ')'", name, f.arity,
                                 f.arity >= 2 ? "s" : ""));
        }
        token_start_ = name_start;  // a dimension error names the function
        return Push({f.op, 0, -1, a, b, c3});
      }
      if (const Symbol* table = symbols_.Find(name); table != nullptr && table->kind == Op::kTable) {
        const DepthGuard guard(*this);
        ++pos_;
        const Table& t = (*symbols_.tables())[static_cast<std::size_t>(table->index)];
        const int a = ParseExpr();
        if (t.two_d()) {
          if (!Accept(",")) {
            token_start_ = name_start;
            Fail(name, fmt::format("the 2-D table {0} takes two arguments: {0}(x, y)", name));
          }
          const int b = ParseExpr();
          if (!Accept(")")) {
            token_start_ = name_start;
            Fail(name, fmt::format("the 2-D table {0} takes two arguments: {0}(x, y); close it "
                                   "with ')'", name));
          }
          return Push({Op::kTable2, 0, table->index, a, b, -1});
        }
        if (!Accept(")")) {
          token_start_ = name_start;
          Fail(name, fmt::format("the table {0} takes one argument: {0}(x); close it with ')'", name));
        }
        if (e_.nodes_[a].op == Op::kConst) {  // folded: a table at a constant
          double intercept = 0.0, slope = 0.0;
          t.Segment(e_.nodes_[a].value, &intercept, &slope);
          return Push({Op::kConst, intercept + slope * e_.nodes_[a].value, -1, -1, -1, -1});
        }
        return Push({Op::kTable, 0, table->index, a, -1, -1});
      }
      token_start_ = name_start;
      Fail(name, fmt::format("unknown function; known: {} and the file's tables", KnownFunctionList()));
    }
    if (name == "pi") return Push({Op::kConst, std::numbers::pi, -1, -1, -1, -1}, Dim::One());
    const Symbol* s = symbols_.Find(name);
    if (s != nullptr && s->kind == Op::kTable) {
      token_start_ = name_start;
      Fail(name, fmt::format("{0} is a table; call it with its argument: {0}(x)", name));
    }
    if (s == nullptr) {
      token_start_ = name_start;
      std::string hint;
      for (const std::string& c : symbols_.Closest(name)) hint += (hint.empty() ? "" : ", ") + c;
      Fail(name, fmt::format("unknown name; did you mean {}? (names are coordinates, speeds, "
                             "slots, states, parameters, time functions, t and pi)", hint));
    }
    if (s->kind == Op::kConst) return Push({Op::kConst, s->value, -1, -1, -1, -1}, s->dim);
    return Push({s->kind, 0, s->index, -1, -1, -1}, s->dim);
  }

  // velocity(P, F).x: the velocity of point P in N, its component along F's x̂ (y, z alike);
  // angular_velocity(A, F).z: the angular velocity of frame A in N, likewise.
  int ParseVelocity(const std::string& name, std::size_t name_start) {
    const bool angular = name == "angular_velocity";
    const std::string usage = angular ? "angular_velocity(A, F).x (frame A, components in frame F)"
                                      : "velocity(P, F).x (point P, components in frame F)";
    auto fail = [&](const std::string& what) {
      token_start_ = name_start;
      Fail(name, what + "; write " + usage);
    };
    const Mirror* m = symbols_.mirror().get();
    if (m == nullptr) fail("velocities may be used only in forces and torques");
    ++pos_;
    auto word = [&]() {
      Skip();
      const std::size_t start = pos_;
      while (pos_ < text_.size() && IsNameChar(text_[pos_])) ++pos_;
      return std::string(text_.substr(start, pos_ - start));
    };
    const std::string of = word();
    if (!Accept(",")) fail("expected two names");
    const std::string in = word();
    if (!Accept(")") || !Accept(".")) fail("expected ').' and a component");
    Skip();
    const char axis = pos_ < text_.size() ? text_[pos_] : '\0';
    if (axis != 'x' && axis != 'y' && axis != 'z') fail("the component is x, y or z");
    ++pos_;
    const auto& ids = angular ? m->frame_ids : m->point_ids;
    const auto it = ids.find(of);
    if (it == ids.end()) {
      fail(fmt::format("'{}' is not a {} declared before this load", of, angular ? "frame" : "point"));
    }
    const auto frame = m->frame_ids.find(in);
    if (frame == m->frame_ids.end()) fail(fmt::format("'{}' is not a frame", in));
    if (m->num_coordinates > multibody::kMaxJetCoordinates) {
      fail(fmt::format("velocities in loads are supported up to {} coordinates", multibody::kMaxJetCoordinates));
    }
    return Push({angular ? Op::kAngularVelocity : Op::kVelocity,
                 static_cast<double>(3 * frame->second + (axis - 'x')), it->second, -1, -1, -1},
                angular ? Dim{true, {0, 0, -1}} : Dim{true, {1, 0, -1}});
  }

  std::string_view text_;
  const SymbolTable& symbols_;
  std::size_t pos_ = 0;
  std::size_t token_start_ = 0;
  int recursion_ = 0;
  std::vector<int> depth_;  // depth of each node's sub-tree
  std::vector<Dim> dims_;   // dimension of each node's value
  Expression e_;
};

Expression Expression::Parse(std::string_view text, const SymbolTable& symbols) {
  Expression e = Parser(text, symbols).Run();
  // Keep only the nodes reachable from the root, children before parents (folded constants
  // leave their operands behind).
  Expression out;
  std::vector<int> map(e.nodes_.size(), -1);
  auto copy = [&](auto&& self, int i) -> int {
    if (map[i] >= 0) return map[i];
    Node n = e.nodes_[i];
    if (n.a >= 0) n.a = self(self, n.a);
    if (n.b >= 0) n.b = self(self, n.b);
    if (n.c >= 0) n.c = self(self, n.c);
    out.nodes_.push_back(n);
    return map[i] = static_cast<int>(out.nodes_.size()) - 1;
  };
  out.root_ = copy(copy, e.root_);
  out.dim_ = e.dim_;
  if (out.Uses(Op::kTable) || out.Uses(Op::kTable2)) out.tables_ = symbols.tables();
  if (out.Uses(Op::kVelocity) || out.Uses(Op::kAngularVelocity)) out.mirror_ = symbols.mirror();
  return out;
}
}  // namespace hybridtest::modelfile
