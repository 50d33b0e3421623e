// Symbol tables, constant folding and linearisation of model-file expressions (the parser is in
// expression_parser.cc). See expression.h.
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
#include "hybridtest/modelfile/expression_ops.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile {

void SymbolTable::Add(Symbol symbol) { symbols_.push_back(std::move(symbol)); }

void SymbolTable::AddTable(std::string name, Table table) {
  table.name = name;
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

std::span<const FunctionInfo> KnownFunctions() { return kFunctions; }

std::string_view KnownFunctionList() { return kFunctionList; }

bool IsFunctionName(std::string_view name) {
  for (const FunctionInfo& f : kFunctions) {
    if (name == f.name) return true;
  }
  return false;
}

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
