#pragma once
// A scalar expression of a model file, parsed once into a flat tree and then evaluated, with
// no allocation, for any scalar the engine uses: double, AutoDiff (loads), Jet<double> and
// Jet<AutoDiff> (kinematic fields). See expression_eval.h for evaluation and
// docs/decisions/0006-model-file-expressions.md for why this is a small tree of our own.
//
// Grammar (usual precedence, left-associative, `^` and `**` right-associative):
//   expr    := term (('+' | '-') term)*
//   term    := unary (('*' | '/') unary)*
//   unary   := ('-' | '+') unary | power
//   power   := primary (('^' | '**') unary)?
//   primary := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
//   cond    := expr ('<' | '<=' | '>' | '>=') expr        (only as the first argument of if)
// A number may carry a unit: `30 deg`, `600 mm` (converted to SI at parse time; units.h).
// Functions: sin cos tan exp log sqrt abs tanh asin acos atan sign (one argument), pow min max
// atan2 (two), if(cond, a, b) (the branch selected by value; its derivative is the branch's).
// Constant: pi. A table declared in the file is called like a function: Cp(lambda). In loads,
// velocity(P, F).x and angular_velocity(A, F).z (kinematics_mirror.h).
// Names resolve through a SymbolTable: time t [s], coordinates q_k, speeds u_k, slots r_k,
// extra states z_k, time functions, and parameters (replaced by their SI value at parse time).
// Sub-trees without variables are folded into constants.
//
// Dimensions are followed through the tree as far as it allows (Dim): every name with a unit
// (t, coordinates, speeds, slots, states, parameters declared with `unit:`), a number written
// with a unit (`30 deg`) and velocity() carry one; a bare number, a parameter without a unit
// and a table's value are unknown and match anything. +, −, min, max, comparisons, atan2 and
// the branches of if() must agree; the arguments of sin, cos, exp, … must be dimensionless;
// products and powers combine. A mismatch is a parse error naming both units.
#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::modelfile {

enum class Op {
  kConst, kTime, kCoordinate, kSpeed, kSlot, kTimeFunction,
  kNeg, kAdd, kSub, kMul, kDiv, kPow,
  kSin, kCos, kTan, kExp, kLog, kSqrt, kAbs, kMin, kMax,
  kAtan2, kTanh, kAsin, kAcos, kAtan, kSign,
  kLt, kLe, kGt, kGe,  // comparisons: 1 or 0 (the condition of an `if`)
  kIf,                 // if(a, b, c): b where a ≠ 0, else c
  kTable,              // table `index` at a: piecewise-linear interpolation
  kTable2,             // 2-D table `index` at (a, b): bilinear interpolation
  kVelocity,           // velocity of point `index` in N; value = 3 · frame + component
  kAngularVelocity,    // angular velocity of frame `index` in N; value as for kVelocity
  kState,              // extra first-order state z_k (`states:`), k = index
};

// The frames and points of a model file as read, for velocity() and angular_velocity() in
// loads (kinematics_mirror.h).
struct Mirror;

// A 1-D table y(x) from a model file: piecewise-linear between the points (x strictly
// increasing, at least two), constant beyond the ends (the end values, slope 0).
struct Table {
  std::string name;  // as the file names it (a printed equation shows name(x))
  std::vector<double> x, y;
  // 2-D tables: z(x, y) on the grid x × y, row-major (z[i · |y| + j] at x_i, y_j), bilinear in
  // each cell, clamped to the grid beyond its edges. Empty for a 1-D table y(x).
  std::vector<double> z;
  bool two_d() const { return !z.empty(); }
  // 1-D: the value at `at` is intercept + slope · at on its segment (slope 0 beyond the ends).
  void Segment(double at, double* intercept, double* slope) const;
};

// The cell of `grid` (strictly increasing) holding `at`: index i of its left edge, and whether
// `at` is clamped to the left (−1) or right (+1) edge of the grid, or inside (0).
int GridCell(const std::vector<double>& grid, double at, int* clamped);

// Whether `name` is one of the built-in functions (sin, atan2, if, ...).
bool IsFunctionName(std::string_view name);

struct Node {
  Op op = Op::kConst;
  double value = 0.0;  // kConst
  int index = -1;      // kCoordinate, kSpeed, kSlot, kTimeFunction, kState: 0-based index
  int a = -1;          // first operand (node index)
  int b = -1;          // second operand
  int c = -1;          // third operand (kIf)
};

// Expressions nest at most this deep (parentheses, calls and chains of operators): deeper ones
// are refused at parse time, so that parsing and evaluation (both recursive) cannot overflow the
// stack. A formula this deep is better split into parameters or time functions.
inline constexpr int kMaxExpressionDepth = 200;

// A physical dimension: the exponents of m, kg and s, radians counting as 1 (so ω·R is a
// speed and k·β with k in N·m/rad a moment); or unknown, which matches any dimension.
struct Dim {
  bool known = false;
  std::array<int, 3> e{0, 0, 0};  // m, kg, s
  // The dimension of a unit's exponents (m, kg, s, rad; units.h); `known` true.
  static Dim FromUnit(const std::array<int, 4>& unit_dim) {
    return {true, {unit_dim[0], unit_dim[1], unit_dim[2]}};
  }
  static Dim One() { return {true, {0, 0, 0}}; }
  // The dimension of a unit written as text (`N·m/rad`), unknown if it does not parse.
  static Dim OfUnit(std::string_view unit_text);
  bool operator==(const Dim& o) const { return known == o.known && e == o.e; }
};
// The dimension as SI base units: "kg·m/s²", "m", "1"; "unknown".
std::string DimName(const Dim& d);
// The dimension of `op` applied to operands of dimensions a, b, c (c: if()'s else branch;
// constant_b, b_value: a constant exponent of pow). On a mismatch, `error` gets what is wrong
// (dimensions.cc).
Dim CombineDims(Op op, const Dim& a, const Dim& b, const Dim& c, bool constant_b, double b_value,
                std::string* error);

// What a name means in an expression.
struct Symbol {
  std::string name;
  Op kind = Op::kConst;  // kConst (parameter or constant), kTime, kCoordinate, kSpeed, ...
  int index = -1;
  double value = 0.0;  // kConst: SI value
  Dim dim = {};        // its dimension, if known
};

class SymbolTable {
 public:
  void Add(Symbol symbol);
  // Declares a table, called as NAME(x) in expressions.
  void AddTable(std::string name, Table table);
  const std::shared_ptr<std::vector<Table>>& tables() const { return tables_; }
  // The frames and points velocity() may name (set by the model-file reader; null: none).
  void SetMirror(std::shared_ptr<const Mirror> mirror) { mirror_ = std::move(mirror); }
  const std::shared_ptr<const Mirror>& mirror() const { return mirror_; }
  const Symbol* Find(std::string_view name) const;
  // Up to three known names closest to `name` (edit distance), for "did you mean" hints.
  std::vector<std::string> Closest(std::string_view name) const;

 private:
  std::vector<Symbol> symbols_;
  std::shared_ptr<std::vector<Table>> tables_ = std::make_shared<std::vector<Table>>();
  std::shared_ptr<const Mirror> mirror_;
};

// A parse error: `column` (0-based) and the offending `token` in the expression text.
struct ExpressionError {
  int column = 0;
  std::string token;
  std::string message;  // what is wrong and how to fix it
};

class Expression {
 public:
  // Parses `text` against `symbols`. Throws ExpressionError.
  static Expression Parse(std::string_view text, const SymbolTable& symbols);
  static Expression Constant(double value);

  const std::vector<Node>& nodes() const { return nodes_; }
  int root() const { return root_; }
  bool is_constant() const { return nodes_[root_].op == Op::kConst; }
  double constant_value() const { return nodes_[root_].value; }
  // The dimension of the value, as far as the tree tells (Dim).
  const Dim& dim() const { return dim_; }
  // True if any node is of kind `op` (e.g. kSpeed: the expression reads a speed).
  bool Uses(Op op) const;
  // The tables kTable nodes index (shared with the symbol table it was parsed against).
  const Table* tables() const { return tables_ ? tables_->data() : nullptr; }
  const Mirror* mirror() const { return mirror_.get(); }

 private:
  friend class Parser;
  std::vector<Node> nodes_;
  int root_ = 0;
  Dim dim_;
  std::shared_ptr<const std::vector<Table>> tables_;
  std::shared_ptr<const Mirror> mirror_;
};

// An expression as c0 + Σ c_i v_i over variables (t, q_k, u_k, r_k, z_k, time functions), if it
// is affine in them with constant coefficients; `affine` is false otherwise.
struct LinearForm {
  struct Term {
    Op kind;     // kTime, kCoordinate, kSpeed, kSlot, kTimeFunction, kState
    int index;   // −1 for kTime
    double coefficient;
  };
  bool affine = false;
  double constant = 0.0;
  std::vector<Term> terms;
};
LinearForm Linearize(const Expression& e);

}  // namespace hybridtest::modelfile
