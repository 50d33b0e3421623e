#pragma once
// A model-file expression ready for the engine: its affine form when it has one (evaluated as
// a flat sum, c0 + Σ c_i v_i), the expression tree otherwise. Used for loads and time
// functions (scalars double and AutoDiff).
#include "hybridtest/modelfile/expression_eval.h"

namespace hybridtest::modelfile {

struct CompiledScalar {
  explicit CompiledScalar(Expression e) : expression(std::move(e)), linear(Linearize(expression)) {}

  template <typename S>
  S Eval(const Variables<S>& v) const {
    if (!linear.affine) return Evaluate(expression, v);
    S sum(linear.constant);
    for (const LinearForm::Term& term : linear.terms) {
      sum += term.coefficient * Variable(term, v);
    }
    return sum;
  }

  Expression expression;
  LinearForm linear;

 private:
  template <typename S>
  static const S& Variable(const LinearForm::Term& term, const Variables<S>& v) {
    const auto k = static_cast<std::size_t>(term.index);
    switch (term.kind) {
      case Op::kCoordinate: return v.q[k];
      case Op::kSpeed: return v.u[k];
      case Op::kSlot: return v.r[k];
      case Op::kTimeFunction: return v.time_values[k];
      case Op::kState: return v.z[k];
      default: return v.t;
    }
  }
};

}  // namespace hybridtest::modelfile
