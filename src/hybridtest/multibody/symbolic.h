#pragma once
// Symbolic: the Kane engine's third scalar (decision 0019). A thin value type over a GiNaC
// expression (GiNaC::ex), so that the same Calc* code that computes M and the forcing in double
// yields them as expressions in the model's coordinates, speeds, time and restoring forces.
//
// GiNaC stays out of this header: the expression is held behind a shared pointer and every
// operation is a call into symbolic.cc. Model code (generic lambdas) therefore compiles for
// Symbolic without GiNaC's headers, and only the printers (src/hybridtest/symbolic/) see
// GiNaC::ex. There are deliberately no ordering operators (<, >): a branch on a value has no
// symbolic meaning, and the compiler points at every place that would take one. == and != are
// structural (the same expression), which is what Eigen asks of a scalar.
//
// Not for the real-time path: every operation allocates.
#include <Eigen/Core>
#include <memory>
#include <string>

namespace GiNaC {
class ex;
class numeric;
}  // namespace GiNaC

namespace hybridtest::multibody {

class Symbolic {
 public:
  Symbolic();                    // 0
  // A number becomes the exact rational of its shortest decimal (0.65 → 13/20; issue 47), so
  // that the expressions' arithmetic is exact and independent of GiNaC's term order.
  Symbolic(double value);        // NOLINT: numbers convert implicitly, as for double
  explicit Symbolic(const GiNaC::ex& e);
  // A new symbol named `name` (e.g. "q1"), real.
  static Symbolic Variable(const std::string& name);

  const GiNaC::ex& ex() const;

  Symbolic& operator+=(const Symbolic& b);
  Symbolic& operator-=(const Symbolic& b);
  Symbolic& operator*=(const Symbolic& b);
  Symbolic& operator/=(const Symbolic& b);

 private:
  std::shared_ptr<const GiNaC::ex> e_;  // null: 0
};

Symbolic operator+(const Symbolic& a, const Symbolic& b);
Symbolic operator-(const Symbolic& a, const Symbolic& b);
Symbolic operator*(const Symbolic& a, const Symbolic& b);
Symbolic operator/(const Symbolic& a, const Symbolic& b);
Symbolic operator-(const Symbolic& a);
Symbolic operator+(const Symbolic& a);
bool operator==(const Symbolic& a, const Symbolic& b);  // structurally equal
bool operator!=(const Symbolic& a, const Symbolic& b);

Symbolic sin(const Symbolic& a);
Symbolic cos(const Symbolic& a);
Symbolic tan(const Symbolic& a);
Symbolic exp(const Symbolic& a);
Symbolic log(const Symbolic& a);
Symbolic sqrt(const Symbolic& a);
Symbolic pow(const Symbolic& a, double p);
Symbolic pow(const Symbolic& a, const Symbolic& p);
Symbolic atan(const Symbolic& a);
Symbolic asin(const Symbolic& a);
Symbolic acos(const Symbolic& a);
Symbolic tanh(const Symbolic& a);
Symbolic atan2(const Symbolic& y, const Symbolic& x);
Symbolic abs(const Symbolic& a);
Symbolic sign(const Symbolic& a);  // −1, 0, +1 (GiNaC's csgn on reals)
// f(a) for an uninterpreted smooth function named `name` (a model file's table).
Symbolic ApplyFunction(const std::string& name, const Symbolic& a);

// The exact rational of v's shortest decimal (0.65 → 13/20), as every number becomes when it
// enters a Symbolic; non-finite values stay floats.
GiNaC::numeric ExactDecimal(double v);

}  // namespace hybridtest::multibody

namespace Eigen {
template <>
struct NumTraits<hybridtest::multibody::Symbolic> : GenericNumTraits<double> {
  using Real = hybridtest::multibody::Symbolic;
  using NonInteger = hybridtest::multibody::Symbolic;
  using Nested = hybridtest::multibody::Symbolic;
  using Literal = double;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 3,
    MulCost = 3
  };
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<hybridtest::multibody::Symbolic, double, BinaryOp> {
  using ReturnType = hybridtest::multibody::Symbolic;
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, hybridtest::multibody::Symbolic, BinaryOp> {
  using ReturnType = hybridtest::multibody::Symbolic;
};
}  // namespace Eigen
