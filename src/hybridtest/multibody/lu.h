#pragma once
// Internal to the engine: a small dense LU factorisation with partial pivoting, in place, on
// any engine scalar (pivots chosen by value, so AutoDiff carries exact derivatives through).
// Used by the constrained equations (constraints.h); allocation-free.
#include <cmath>

#include "hybridtest/multibody/scalar.h"

namespace hybridtest::multibody::internal {

// Factors the leading k × k block of `a` in place (P a = L U, unit L below the diagonal).
// Returns false if a pivot is below 1e-13 of the block's largest entry (singular).
template <typename T>
bool LuFactor(MatrixX<T>& a, int k, int* pivots) {
  double scale = 0.0;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) scale = std::max(scale, std::abs(ValueOf(a(i, j))));
  for (int c = 0; c < k; ++c) {
    int best = c;
    for (int i = c + 1; i < k; ++i) {
      if (std::abs(ValueOf(a(i, c))) > std::abs(ValueOf(a(best, c)))) best = i;
    }
    pivots[c] = best;
    if (!(std::abs(ValueOf(a(best, c))) > 1e-13 * scale)) return false;
    if (best != c) {
      for (int j = 0; j < k; ++j) std::swap(a(c, j), a(best, j));
    }
    const T inv = T(1.0) / a(c, c);
    for (int i = c + 1; i < k; ++i) {
      const T f = T(a(i, c) * inv);
      a(i, c) = f;
      for (int j = c + 1; j < k; ++j) a(i, j) = T(a(i, j) - f * a(c, j));
    }
  }
  return true;
}

// Solves with the factor of LuFactor: b (k) is replaced by the solution.
template <typename T>
void LuSolve(const MatrixX<T>& a, int k, const int* pivots, T* b) {
  for (int c = 0; c < k; ++c) {
    if (pivots[c] != c) std::swap(b[c], b[pivots[c]]);
  }
  for (int i = 0; i < k; ++i) {
    T s = b[i];
    for (int j = 0; j < i; ++j) s = T(s - a(i, j) * b[j]);
    b[i] = s;
  }
  for (int i = k - 1; i >= 0; --i) {
    T s = b[i];
    for (int j = i + 1; j < k; ++j) s = T(s - a(i, j) * b[j]);
    b[i] = T(s / a(i, i));
  }
}

}  // namespace hybridtest::multibody::internal
