// Parsing, constant folding and linearisation of model-file expressions. See expression.h.
#include "hybridtest/modelfile/expression.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>

#include "hybridtest/modelfile/kinematics_mirror.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile {

void SymbolTable::Add(Symbol symbol) { symbols_.push_back(std::move(symbol)); }

void SymbolTable::AddTable(std::string name, Table table) {
  tables_->push_back(std::move(table));
  Add({std::move(name), Op::kTable, static_cast<int>(tables_->size()) - 1, 0.0});
}

int GridCell(const std::vector<double>& grid, double at, int* clamped) {
  const int last = static_cast<int>(grid.size()) - 2;
  if (!(at > grid.front())) {
    *clamped = -1;
    return 0;
  }
  if (at >= grid.back()) {
    *clamped = 1;
    return last;
  }
  *clamped = 0;
  return static_cast<int>(std::upper_bound(grid.begin(), grid.end(), at) - grid.begin()) - 1;
}

void Table::Segment(double at, double* intercept, double* slope) const {
  if (!(at > x.front())) {  // also NaN: the first value
    *intercept = y.front();
    *slope = 0.0;
    return;
  }
  if (at >= x.back()) {
    *intercept = y.back();
    *slope = 0.0;
    return;
  }
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin()) - 1;
  *slope = (y[k + 1] - y[k]) / (x[k + 1] - x[k]);
  *intercept = y[k] - *slope * x[k];
}

const Symbol* SymbolTable::Find(std::string_view name) const {
  for (const Symbol& s : symbols_) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

namespace {
int EditDistance(std::string_view a, std::string_view b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}
}  // namespace

std::vector<std::string> SymbolTable::Closest(std::string_view name) const {
  // By edit distance, ties broken by the longer common prefix ("lenght" → l before t).
  std::vector<std::pair<int, std::string>> scored;
  for (const Symbol& s : symbols_) {
    std::size_t prefix = 0;
    while (prefix < name.size() && prefix < s.name.size() && name[prefix] == s.name[prefix]) ++prefix;
    scored.emplace_back(4 * EditDistance(name, s.name) - static_cast<int>(std::min<std::size_t>(prefix, 3)),
                        s.name);
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < scored.size() && i < 3; ++i) out.push_back(scored[i].second);
  return out;
}

namespace {
struct FunctionInfo {
  const char* name;
  Op op;
  int arity;
};
constexpr FunctionInfo kFunctions[] = {
    {"sin", Op::kSin, 1},   {"cos", Op::kCos, 1},   {"tan", Op::kTan, 1},
    {"exp", Op::kExp, 1},   {"log", Op::kLog, 1},   {"sqrt", Op::kSqrt, 1},
    {"abs", Op::kAbs, 1},   {"pow", Op::kPow, 2},   {"min", Op::kMin, 2},
    {"max", Op::kMax, 2},   {"atan2", Op::kAtan2, 2}, {"tanh", Op::kTanh, 1},
    {"asin", Op::kAsin, 1}, {"acos", Op::kAcos, 1}, {"atan", Op::kAtan, 1},
    {"sign", Op::kSign, 1}, {"if", Op::kIf, 3},
};
constexpr char kFunctionList[] =
    "sin cos tan exp log sqrt abs tanh asin acos atan sign (one argument), pow min max atan2 "
    "(two), if(cond, a, b)";

}  // namespace

bool IsFunctionName(std::string_view name) {
  for (const FunctionInfo& f : kFunctions) {
    if (name == f.name) return true;
  }
  return false;
}

namespace {
bool IsNameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool IsNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Value of a unary or binary operation on constants.
double Fold(Op op, double a, double b) {
  switch (op) {
    case Op::kNeg: return -a;
    case Op::kAdd: return a + b;
    case Op::kSub: return a - b;
    case Op::kMul: return a * b;
    case Op::kDiv: return a / b;
    case Op::kPow: return std::pow(a, b);
    case Op::kSin: return std::sin(a);
    case Op::kCos: return std::cos(a);
    case Op::kTan: return std::tan(a);
    case Op::kExp: return std::exp(a);
    case Op::kLog: return std::log(a);
    case Op::kSqrt: return std::sqrt(a);
    case Op::kAbs: return std::abs(a);
    case Op::kMin: return std::min(a, b);
    case Op::kMax: return std::max(a, b);
    case Op::kAtan2: return std::atan2(a, b);
    case Op::kTanh: return std::tanh(a);
    case Op::kAsin: return std::asin(a);
    case Op::kAcos: return std::acos(a);
    case Op::kAtan: return std::atan(a);
    case Op::kSign: return a > 0.0 ? 1.0 : a < 0.0 ? -1.0 : 0.0;
    case Op::kLt: return a < b ? 1.0 : 0.0;
    case Op::kLe: return a <= b ? 1.0 : 0.0;
    case Op::kGt: return a > b ? 1.0 : 0.0;
    case Op::kGe: return a >= b ? 1.0 : 0.0;
    default: return a;
  }
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
      for (const FunctionInfo& f : kFunctions) {
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
      Fail(name, fmt::format("unknown function; known: {} and the file's tables", kFunctionList));
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

Expression Expression::Constant(double value) {
  Expression e;
  e.nodes_.push_back({Op::kConst, value, -1, -1, -1, -1});
  return e;
}

bool Expression::Uses(Op op) const {
  return std::any_of(nodes_.begin(), nodes_.end(), [op](const Node& n) { return n.op == op; });
}

namespace {
using Key = std::pair<int, int>;  // (kind, index)
struct Affine {
  bool ok = true;
  double c = 0.0;
  std::map<Key, double> terms;
};
Affine Scale(Affine a, double s) {
  a.c *= s;
  for (auto& kv : a.terms) kv.second *= s;
  return a;
}
Affine Combine(Affine a, const Affine& b, double sb) {
  a.ok = a.ok && b.ok;
  a.c += sb * b.c;
  for (const auto& kv : b.terms) a.terms[kv.first] += sb * kv.second;
  return a;
}
Affine LinearizeNode(const std::vector<Node>& nodes, int i) {
  const Node& n = nodes[i];
  Affine r;
  switch (n.op) {
    case Op::kConst: r.c = n.value; return r;
    case Op::kTime: case Op::kCoordinate: case Op::kSpeed: case Op::kSlot:
    case Op::kTimeFunction: case Op::kState:
      r.terms[{static_cast<int>(n.op), n.op == Op::kTime ? -1 : n.index}] = 1.0;
      return r;
    case Op::kNeg: return Scale(LinearizeNode(nodes, n.a), -1.0);
    case Op::kAdd: return Combine(LinearizeNode(nodes, n.a), LinearizeNode(nodes, n.b), 1.0);
    case Op::kSub: return Combine(LinearizeNode(nodes, n.a), LinearizeNode(nodes, n.b), -1.0);
    case Op::kMul: {
      if (nodes[n.a].op == Op::kConst) return Scale(LinearizeNode(nodes, n.b), nodes[n.a].value);
      if (nodes[n.b].op == Op::kConst) return Scale(LinearizeNode(nodes, n.a), nodes[n.b].value);
      break;
    }
    case Op::kDiv:
      if (nodes[n.b].op == Op::kConst) return Scale(LinearizeNode(nodes, n.a), 1.0 / nodes[n.b].value);
      break;
    default: break;
  }
  r.ok = false;
  return r;
}
}  // namespace

LinearForm Linearize(const Expression& e) {
  const Affine a = LinearizeNode(e.nodes(), e.root());
  LinearForm f;
  if (!a.ok) return f;
  f.affine = true;
  f.constant = a.c;
  for (const auto& [key, c] : a.terms) {
    if (c != 0.0) f.terms.push_back({static_cast<Op>(key.first), key.second, c});
  }
  return f;
}

}  // namespace hybridtest::modelfile
