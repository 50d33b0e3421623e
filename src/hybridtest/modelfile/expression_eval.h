#pragma once
// Evaluation of a parsed Expression (expression.h) for any engine scalar S: double and
// AutoDiff for loads, Jet<double> and Jet<AutoDiff> for kinematic fields. A recursive walk
// over the flat node array; every temporary lives on the stack (no heap allocation).
#include <cmath>
#include <span>

#include "hybridtest/modelfile/expression.h"
#include "hybridtest/multibody/jet.h"
#include "hybridtest/multibody/scalar.h"

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
};

namespace eval_detail {
inline double Value(double x) { return x; }
inline double Value(const multibody::AutoDiff& x) { return x.value(); }
template <typename T>
double Value(const multibody::Jet<T>& x) { return Value(x.v); }

template <typename S>
S PowConstant(const S& a, double p) {
  using std::pow;
  return S(pow(a, p));
}

template <typename S>
S Eval(const Node* nodes, int i, const Variables<S>& v) {
  using std::cos; using std::exp; using std::log; using std::sin; using std::sqrt; using std::tan;
  const Node& n = nodes[i];
  switch (n.op) {
    case Op::kConst: return S(n.value);
    case Op::kTime: return v.t;
    case Op::kCoordinate: return v.q[static_cast<std::size_t>(n.index)];
    case Op::kSpeed: return v.u[static_cast<std::size_t>(n.index)];
    case Op::kSlot: return v.r[static_cast<std::size_t>(n.index)];
    case Op::kTimeFunction: return v.time_values[static_cast<std::size_t>(n.index)];
    case Op::kNeg: return S(-Eval(nodes, n.a, v));
    case Op::kAdd: return S(Eval(nodes, n.a, v) + Eval(nodes, n.b, v));
    case Op::kSub: return S(Eval(nodes, n.a, v) - Eval(nodes, n.b, v));
    case Op::kMul: {
      // A constant factor multiplies as a double (cheaper for jets and AutoDiff).
      if (nodes[n.a].op == Op::kConst) return S(nodes[n.a].value * Eval(nodes, n.b, v));
      if (nodes[n.b].op == Op::kConst) return S(Eval(nodes, n.a, v) * nodes[n.b].value);
      return S(Eval(nodes, n.a, v) * Eval(nodes, n.b, v));
    }
    case Op::kDiv:
      if (nodes[n.b].op == Op::kConst) return S(Eval(nodes, n.a, v) * (1.0 / nodes[n.b].value));
      return S(Eval(nodes, n.a, v) / Eval(nodes, n.b, v));
    case Op::kPow: {
      const S a = Eval(nodes, n.a, v);
      if (nodes[n.b].op == Op::kConst) return PowConstant(a, nodes[n.b].value);
      return S(exp(Eval(nodes, n.b, v) * log(a)));
    }
    case Op::kSin: return S(sin(Eval(nodes, n.a, v)));
    case Op::kCos: return S(cos(Eval(nodes, n.a, v)));
    case Op::kTan: return S(tan(Eval(nodes, n.a, v)));
    case Op::kExp: return S(exp(Eval(nodes, n.a, v)));
    case Op::kLog: return S(log(Eval(nodes, n.a, v)));
    case Op::kSqrt: return S(sqrt(Eval(nodes, n.a, v)));
    case Op::kAbs: {
      const S a = Eval(nodes, n.a, v);
      return Value(a) < 0.0 ? S(-a) : a;
    }
    case Op::kMin: case Op::kMax: {
      const S a = Eval(nodes, n.a, v);
      const S b = Eval(nodes, n.b, v);
      const bool a_less = Value(a) < Value(b);
      return (n.op == Op::kMin) == a_less ? a : b;
    }
  }
  return S(0.0);
}
}  // namespace eval_detail

// The value of `e` at `v`.
template <typename S>
S Evaluate(const Expression& e, const Variables<S>& v) {
  return eval_detail::Eval(e.nodes().data(), e.root(), v);
}

}  // namespace hybridtest::modelfile
