#pragma once
// Expressions a model is written with, and how the engine stores them.
//
// ScalarField: a scalar function φ(q, t) — a rotation angle, a component of a position
// vector, a restoring-force slot's displacement. Either affine, φ = c0 + Σ c_k q_k + c_t t
// (the common case, evaluated with no function call), or a general smooth function given as a
// generic lambda `[](const auto& a) { return l * cos(a.q[2]) + a.t; }`, evaluated on Jets so
// the engine gets exact first and second time derivatives and ∂φ/∂q.
//
// Loads (forces and torques) are generic lambdas of (t, q, u, r) returning a 3-vector in a
// chosen frame; the engine calls them with T = double, T = AutoDiff, or T = Symbolic (to print
// the equations, decision 0019). Model parameters are
// captured by the lambdas (a model is rebuilt when a parameter changes).
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "hybridtest/multibody/jet.h"
#include "hybridtest/multibody/scalar.h"
#include "hybridtest/multibody/symbolic.h"

namespace hybridtest::multibody {

// Inputs of a kinematic expression: coordinates q (n jets) and time t [s] (a jet).
template <typename T>
struct KinematicArgs {
  std::span<const Jet<T>> q;
  Jet<T> t;
};

// Inputs of a load: time [s], coordinates q, speeds u, static restoring forces r^s [N] (one
// per slot), the values of the model's time functions at t (ModelBuilder::
// AddTimeFunction, evaluated once per CalcForcing and shared by all loads; unit: whatever the
// function returns), and the extra first-order states z (ModelBuilder::AddExtraState; each in
// its own unit). Loads must be linear in r (the hybrid coupling relies on it). The rate of an
// extra state gets the same inputs with r empty: ż may not depend on r.
template <typename T>
struct LoadArgs {
  T t;
  std::span<const T> q;
  std::span<const T> u;
  std::span<const T> r;
  std::span<const T> time_values;  // (num_time_functions)
  std::span<const T> z = {};       // (num_extra_states)
  // Value of time function k (the index AddTimeFunction returned) at t.
  const T& time_function(int k) const { return time_values[static_cast<std::size_t>(k)]; }
};

// One callable per supported scalar type, all made from the same generic lambda.
template <template <typename> class Signature>
class MultiScalarFunction {
 public:
  MultiScalarFunction() = default;
  template <class F>
  explicit MultiScalarFunction(const F& f)
      : for_double_(f), for_autodiff_(f), for_symbolic_(f) {}
  explicit operator bool() const { return static_cast<bool>(for_double_); }
  template <typename T>
  const std::function<Signature<T>>& get() const {
    if constexpr (std::is_same_v<T, double>) {
      return for_double_;
    } else if constexpr (std::is_same_v<T, AutoDiff>) {
      return for_autodiff_;
    } else {
      static_assert(std::is_same_v<T, Symbolic>, "the engine's scalars: double, AutoDiff, Symbolic");
      return for_symbolic_;
    }
  }

 private:
  std::function<Signature<double>> for_double_;
  std::function<Signature<AutoDiff>> for_autodiff_;
  std::function<Signature<Symbolic>> for_symbolic_;  // printing only (decision 0019)
};

template <typename T> using ScalarSignature = Jet<T>(const KinematicArgs<T>&);
// Fills `out` (9 jets, row-major) with the direction-cosine matrix R_PF: column j holds the
// child frame's j-th unit vector expressed in the parent frame.
template <typename T> using DcmSignature = void(const KinematicArgs<T>&, std::span<Jet<T>> out);
// Fills `W` (n×n jets, row-major) of the kinematical differential equations q̇ = W(q) u.
template <typename T> using KinematicMatrixSignature =
    void(const KinematicArgs<T>&, std::span<Jet<T>> W);
template <typename T> using LoadSignature = Vector3<T>(const LoadArgs<T>&);
// The rate ż_k of an extra first-order state (ModelBuilder::AddExtraState).
template <typename T> using RateSignature = T(const LoadArgs<T>&);
// A function of time alone, f(t) (ModelBuilder::AddTimeFunction).
template <typename T> using TimeSignature = T(const T&);

class ScalarField {
 public:
  struct Term {
    int coordinate;  // index k of q_k (0-based)
    double coefficient;
  };

  ScalarField() = default;  // zero
  static ScalarField Constant(double value);
  // scale · q_k + offset
  static ScalarField Coordinate(int k, double scale = 1.0, double offset = 0.0);
  // constant + Σ coefficient·q_k + time_rate·t
  static ScalarField Affine(double constant, std::vector<Term> terms, double time_rate = 0.0);
  // Any smooth expression: f(const KinematicArgs<T>&) -> Jet<T> for T = double and AutoDiff.
  template <class F>
  static ScalarField Function(const F& f) {
    ScalarField field;
    field.function_ = MultiScalarFunction<ScalarSignature>(f);
    return field;
  }

  bool is_affine() const { return !function_; }
  bool is_constant() const { return is_affine() && terms_.empty() && time_rate_ == 0.0; }
  double constant() const { return constant_; }
  const std::vector<Term>& terms() const { return terms_; }
  double time_rate() const { return time_rate_; }
  const MultiScalarFunction<ScalarSignature>& function() const { return function_; }
  // Largest coordinate index used by an affine field (−1 if none).
  int max_coordinate() const;

 private:
  double constant_ = 0.0;
  std::vector<Term> terms_;
  double time_rate_ = 0.0;
  MultiScalarFunction<ScalarSignature> function_;
};

using DcmFunction = MultiScalarFunction<DcmSignature>;
using KinematicMatrixFunction = MultiScalarFunction<KinematicMatrixSignature>;
using LoadFunction = MultiScalarFunction<LoadSignature>;
using TimeFunction = MultiScalarFunction<TimeSignature>;
using RateFunction = MultiScalarFunction<RateSignature>;

}  // namespace hybridtest::multibody
