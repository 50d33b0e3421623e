#pragma once
// Scalar types the Kane engine is instantiated for, and the small fixed-size linear-algebra
// aliases it uses. `double` is the fast path; `AutoDiff` (forward-mode dual numbers with at
// most kMaxDerivatives directions, stored inline: no heap) gives exact partial derivatives,
// e.g. the coupling matrix ∂g/∂r or the Jacobian ∂ẋ/∂x.
#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

namespace hybridtest::multibody {

inline constexpr int kMaxDerivatives = 16;
using Derivatives = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDerivatives, 1>;
using AutoDiff = Eigen::AutoDiffScalar<Derivatives>;

template <typename T> using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T> using Matrix3 = Eigen::Matrix<T, 3, 3>;
template <typename T> using VectorX = Eigen::Matrix<T, Eigen::Dynamic, 1>;
template <typename T> using MatrixX = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <typename T> using Matrix3X = Eigen::Matrix<T, 3, Eigen::Dynamic>;

// The value part of a scalar (identity for double).
inline double ValueOf(double x) { return x; }
inline double ValueOf(const AutoDiff& x) { return x.value(); }

}  // namespace hybridtest::multibody
