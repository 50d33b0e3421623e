#pragma once
// Evaluation of a parsed Expression (expression.h) for any engine scalar S: double and
// AutoDiff for loads, Jet<double> and Jet<AutoDiff> for kinematic fields. A recursive walk
// over the flat node array; every temporary lives on the stack (no heap allocation).
#include <cmath>
#include <span>
#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/expression.h"
#include "hybridtest/multibody/jet.h"
#include "hybridtest/multibody/scalar.h"
#include "hybridtest/multibody/symbolic.h"

namespace hybridtest::modelfile {

// The variables an expression reads, as scalars of type S. Spans a given expression does not
// use may be empty (the model-file builder refuses, e.g., speeds in a kinematic expression).
template <typename S>
struct Variables {
  S t;                        // time [s]
  std::span<const S> q;       // coordinates
  std::span<const S> u;       // speeds
  std::span<const S> r;       // static restoring forces, one per slot
  std::span<const S> time_values;  // the model's time functions at t
  std::span<const S> z = {};  // extra first-order states (`states:`); empty where unused
};

namespace eval_detail {
struct EvalData {
  const Table* tables;
  const Mirror* mirror;
};
}  // namespace eval_detail

// Component `component` (in frame `frame`'s unit vectors) of the velocity of point `id` in N
// (or, `angular`, of the angular velocity of frame `id` in N). kinematics_mirror.h.
template <typename S>
S MirrorVelocity(const Mirror& m, bool angular, int id, int frame, int component,
                 const Variables<S>& v);

namespace eval_detail {
inline double Value(double x) { return x; }
inline double Value(const multibody::AutoDiff& x) { return x.value(); }
// Symbolic (printing the equations, decision 0019) has no value to branch on.
[[noreturn]] inline double Value(const multibody::Symbolic&) {
  throw ModelError("this model file cannot be printed symbolically: an expression branches on a "
                   "value (min, max, a comparison, if, a 2-D table, or abs, sign, atan2 or a "
                   "table inside a kinematic expression); `equations` prints smooth models and "
                   "1-D tables, abs, sign and atan2 in loads");
}
template <typename T>
double Value(const multibody::Jet<T>& x) { return Value(x.v); }

// The functions the engine's scalars do not all provide (atan, asin, acos, tanh): on double
// directly, on AutoDiff by the chain rule, on Jet<T> by jet_detail::Chain with the first and
// second derivatives computed in T (so Jet<AutoDiff> stays exact too).
inline multibody::AutoDiff ChainAD(const multibody::AutoDiff& x, double f, double df) {
  return multibody::AutoDiff(f, x.derivatives() * df);
}
inline double Atan(double x) { return std::atan(x); }
inline double Asin(double x) { return std::asin(x); }
inline double Acos(double x) { return std::acos(x); }
inline double Tanh(double x) { return std::tanh(x); }
inline multibody::Symbolic Atan(const multibody::Symbolic& x) { return atan(x); }
inline multibody::Symbolic Asin(const multibody::Symbolic& x) { return asin(x); }
inline multibody::Symbolic Acos(const multibody::Symbolic& x) { return acos(x); }
inline multibody::Symbolic Tanh(const multibody::Symbolic& x) { return tanh(x); }
inline multibody::AutoDiff Atan(const multibody::AutoDiff& x) {
  const double v = x.value();
  return ChainAD(x, std::atan(v), 1.0 / (1.0 + v * v));
}
inline multibody::AutoDiff Asin(const multibody::AutoDiff& x) {
  const double v = x.value();
  return ChainAD(x, std::asin(v), 1.0 / std::sqrt(1.0 - v * v));
}
inline multibody::AutoDiff Acos(const multibody::AutoDiff& x) {
  const double v = x.value();
  return ChainAD(x, std::acos(v), -1.0 / std::sqrt(1.0 - v * v));
}
inline multibody::AutoDiff Tanh(const multibody::AutoDiff& x) {
  const double th = std::tanh(x.value());
  return ChainAD(x, th, 1.0 - th * th);
}
template <typename T>
multibody::Jet<T> Atan(const multibody::Jet<T>& a) {
  const T x = a.v;
  const T d1 = T(1.0) / T(T(1.0) + T(x * x));
  return multibody::jet_detail::Chain(a, Atan(x), d1, T(-2.0 * x * d1 * d1));
}
template <typename T>
multibody::Jet<T> Asin(const multibody::Jet<T>& a) {
  using std::sqrt;
  const T x = a.v;
  const T d1 = T(1.0) / T(sqrt(T(T(1.0) - T(x * x))));
  return multibody::jet_detail::Chain(a, Asin(x), d1, T(x * d1 * d1 * d1));
}
template <typename T>
multibody::Jet<T> Acos(const multibody::Jet<T>& a) {
  using std::sqrt;
  const T x = a.v;
  const T d1 = T(1.0) / T(sqrt(T(T(1.0) - T(x * x))));
  return multibody::jet_detail::Chain(a, Acos(x), T(-d1), T(-x * d1 * d1 * d1));
}
template <typename T>
multibody::Jet<T> Tanh(const multibody::Jet<T>& a) {
  const T th = Tanh(a.v);
  const T d1 = T(T(1.0) - T(th * th));
  return multibody::jet_detail::Chain(a, th, d1, T(-2.0 * th * d1));
}
// atan2(y, x): the derivatives of atan(y/x) (or of −atan(x/y) where |y| > |x|, so that the
// quotient stays bounded), which differ from atan2 by a constant, and atan2's value.
inline double Atan2(double y, double x) { return std::atan2(y, x); }
template <typename S>
S Atan2(const S& y, const S& x) {
  const double yv = Value(y), xv = Value(x);
  const S r = std::abs(xv) >= std::abs(yv) ? S(Atan(S(y / x))) : S(-Atan(S(x / y)));
  return S(r + (std::atan2(yv, xv) - Value(r)));
}

template <typename S>
S PowConstant(const S& a, double p) {
  using std::pow;
  return S(pow(a, p));
}

template <typename S>
S Eval(const Node* nodes, const EvalData& d, int i, const Variables<S>& v) {
  using std::cos; using std::exp; using std::log; using std::sin; using std::sqrt; using std::tan;
  const Node& n = nodes[i];
  if constexpr (std::is_same_v<S, multibody::Symbolic>) {
    // The non-smooth functions as functions of the expression (their values are unknown).
    switch (n.op) {
      case Op::kAbs: return abs(Eval(nodes, d, n.a, v));
      case Op::kSign: return sign(Eval(nodes, d, n.a, v));
      case Op::kAtan2: return atan2(Eval(nodes, d, n.a, v), Eval(nodes, d, n.b, v));
      case Op::kTable:
        return multibody::ApplyFunction(d.tables[n.index].name, Eval(nodes, d, n.a, v));
      case Op::kVelocity: case Op::kAngularVelocity:
        throw ModelError("this model file cannot be printed symbolically: a load uses velocity() "
                         "or angular_velocity(), which `equations` does not print yet; write the "
                         "velocity with the coordinates and speeds instead");
      default: break;
    }
  }
  switch (n.op) {
    case Op::kConst: return S(n.value);
    case Op::kTime: return v.t;
    case Op::kCoordinate: return v.q[static_cast<std::size_t>(n.index)];
    case Op::kSpeed: return v.u[static_cast<std::size_t>(n.index)];
    case Op::kSlot: return v.r[static_cast<std::size_t>(n.index)];
    case Op::kTimeFunction: return v.time_values[static_cast<std::size_t>(n.index)];
    case Op::kState: return v.z[static_cast<std::size_t>(n.index)];
    case Op::kNeg: return S(-Eval(nodes, d, n.a, v));
    case Op::kAdd: return S(Eval(nodes, d, n.a, v) + Eval(nodes, d, n.b, v));
    case Op::kSub: return S(Eval(nodes, d, n.a, v) - Eval(nodes, d, n.b, v));
    case Op::kMul: {
      // A constant factor multiplies as a double (cheaper for jets and AutoDiff).
      if (nodes[n.a].op == Op::kConst) return S(nodes[n.a].value * Eval(nodes, d, n.b, v));
      if (nodes[n.b].op == Op::kConst) return S(Eval(nodes, d, n.a, v) * nodes[n.b].value);
      return S(Eval(nodes, d, n.a, v) * Eval(nodes, d, n.b, v));
    }
    case Op::kDiv:
      if (nodes[n.b].op == Op::kConst) return S(Eval(nodes, d, n.a, v) * (1.0 / nodes[n.b].value));
      return S(Eval(nodes, d, n.a, v) / Eval(nodes, d, n.b, v));
    case Op::kPow: {
      const S a = Eval(nodes, d, n.a, v);
      if (nodes[n.b].op == Op::kConst) return PowConstant(a, nodes[n.b].value);
      return S(exp(Eval(nodes, d, n.b, v) * log(a)));
    }
    case Op::kSin: return S(sin(Eval(nodes, d, n.a, v)));
    case Op::kCos: return S(cos(Eval(nodes, d, n.a, v)));
    case Op::kTan: return S(tan(Eval(nodes, d, n.a, v)));
    case Op::kExp: return S(exp(Eval(nodes, d, n.a, v)));
    case Op::kLog: return S(log(Eval(nodes, d, n.a, v)));
    case Op::kSqrt: return S(sqrt(Eval(nodes, d, n.a, v)));
    case Op::kAbs: {
      const S a = Eval(nodes, d, n.a, v);
      return Value(a) < 0.0 ? S(-a) : a;
    }
    case Op::kMin: case Op::kMax: {
      const S a = Eval(nodes, d, n.a, v);
      const S b = Eval(nodes, d, n.b, v);
      const bool a_less = Value(a) < Value(b);
      return (n.op == Op::kMin) == a_less ? a : b;
    }
    case Op::kAtan2: return Atan2(Eval(nodes, d, n.a, v), Eval(nodes, d, n.b, v));
    case Op::kTanh: return S(Tanh(Eval(nodes, d, n.a, v)));
    case Op::kAsin: return S(Asin(Eval(nodes, d, n.a, v)));
    case Op::kAcos: return S(Acos(Eval(nodes, d, n.a, v)));
    case Op::kAtan: return S(Atan(Eval(nodes, d, n.a, v)));
    case Op::kSign: {
      const double a = Value(Eval(nodes, d, n.a, v));
      return S(a > 0.0 ? 1.0 : a < 0.0 ? -1.0 : 0.0);
    }
    case Op::kLt: case Op::kLe: case Op::kGt: case Op::kGe: {
      const double a = Value(Eval(nodes, d, n.a, v)), b = Value(Eval(nodes, d, n.b, v));
      const bool yes = n.op == Op::kLt ? a < b : n.op == Op::kLe ? a <= b
                     : n.op == Op::kGt ? a > b : a >= b;
      return S(yes ? 1.0 : 0.0);
    }
    case Op::kTable: {
      const S a = Eval(nodes, d, n.a, v);
      double intercept = 0.0, slope = 0.0;
      d.tables[n.index].Segment(Value(a), &intercept, &slope);
      if (slope == 0.0) return S(intercept);
      return S(a * slope + intercept);
    }
    case Op::kTable2: {
      // Bilinear in the cell: z00 + (z10 − z00) s + (z01 − z00) r + (z11 − z10 − z01 + z00) s r,
      // s and r the fractions across the cell (constant 0 or 1 where clamped).
      const Table& t = d.tables[n.index];
      const S a = Eval(nodes, d, n.a, v), b = Eval(nodes, d, n.b, v);
      int ca = 0, cb = 0;
      const int ci = GridCell(t.x, Value(a), &ca), cj = GridCell(t.y, Value(b), &cb);
      const S s = ca != 0 ? S(ca > 0 ? 1.0 : 0.0) : S((a - t.x[ci]) * (1.0 / (t.x[ci + 1] - t.x[ci])));
      const S r = cb != 0 ? S(cb > 0 ? 1.0 : 0.0) : S((b - t.y[cj]) * (1.0 / (t.y[cj + 1] - t.y[cj])));
      const std::size_t ny = t.y.size();
      const auto z = [&](int ii, int jj) { return t.z[static_cast<std::size_t>(ii) * ny + static_cast<std::size_t>(jj)]; };
      const double z00 = z(ci, cj), z10 = z(ci + 1, cj), z01 = z(ci, cj + 1), z11 = z(ci + 1, cj + 1);
      return S(z00 + s * (z10 - z00) + r * (z01 - z00) + S(s * r) * (z11 - z10 - z01 + z00));
    }
    case Op::kVelocity: case Op::kAngularVelocity: {
      // Loads only (double, AutoDiff): the reader refuses velocities in kinematic fields.
      if constexpr (std::is_same_v<S, double> || std::is_same_v<S, multibody::AutoDiff>) {
        const int frame = static_cast<int>(n.value) / 3;
        const int component = static_cast<int>(n.value) % 3;
        return MirrorVelocity<S>(*d.mirror, n.op == Op::kAngularVelocity, n.index, frame,
                                 component, v);
      } else {
        return S(0.0);
      }
    }
    case Op::kIf:
      return Value(Eval(nodes, d, n.a, v)) != 0.0 ? Eval(nodes, d, n.b, v) : Eval(nodes, d, n.c, v);
  }
  return S(0.0);
}
}  // namespace eval_detail

// The value of `e` at `v`.
template <typename S>
S Evaluate(const Expression& e, const Variables<S>& v) {
  return eval_detail::Eval(e.nodes().data(), eval_detail::EvalData{e.tables(), e.mirror()},
                           e.root(), v);
}

}  // namespace hybridtest::modelfile

#include "hybridtest/modelfile/kinematics_mirror.h"  // IWYU pragma: keep
