// The Cholesky factorisation and solve of the mass matrix. See mass_solve.h.
#include "hybridtest/multibody/mass_solve.h"

#include <Eigen/Cholesky>

#include <cmath>
#include <type_traits>

#include "hybridtest/multibody/field_eval.h"

namespace hybridtest::multibody::internal {
namespace {

// Unblocked Cholesky for a dynamic n: Lᵀ goes to `U` (n × n, column-major, so row i of L is
// the contiguous column i of U) and 1/L_jj to `inv_diag`. Raw column-major indexing: for the
// small n of a multibody model this is several times cheaper than Eigen's dynamic-size LLT.
template <typename T>
bool CholeskyFactor(const MatrixX<T>& M, MatrixX<T>& U, VectorX<T>& inv_diag) {
  using std::sqrt;
  const Eigen::Index n = M.rows();
  const T* m = M.data();
  T* u = U.data();
  T* id = inv_diag.data();
  for (Eigen::Index j = 0; j < n; ++j) {
    const T* uj = u + j * n;  // L(j, 0..j−1)
    T d = m[j + j * n];
    for (Eigen::Index k = 0; k < j; ++k) d -= uj[k] * uj[k];
    if (!(ValueOf(d) > 0.0)) return false;
    const T inv = T(1.0) / sqrt(d);
    id[j] = inv;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      T* ui = u + i * n;  // L(i, 0..j)
      T s = m[i + j * n];
      for (Eigen::Index k = 0; k < j; ++k) s -= ui[k] * uj[k];
      ui[j] = s * inv;
    }
  }
  return true;
}

// L z = b, then Lᵀ y = z (z stored in y), with the factor of CholeskyFactor.
template <typename T>
void CholeskySolve(const MatrixX<T>& U, const VectorX<T>& inv_diag, const VectorX<T>& b,
                   VectorX<T>& y) {
  const Eigen::Index n = U.rows();
  const T* u = U.data();
  const T* id = inv_diag.data();
  T* yv = y.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    const T* ui = u + i * n;
    T s = b(i);
    for (Eigen::Index k = 0; k < i; ++k) s -= ui[k] * yv[k];
    yv[i] = s * id[i];
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    T s = yv[i];
    for (Eigen::Index k = i + 1; k < n; ++k) s -= u[i + k * n] * yv[k];
    yv[i] = s * id[i];
  }
}

// The same for a compile-time size N (the loops unroll), skipping the structural zeros of L
// (`nz`, Model::factor_pattern()): the terms it skips are exact zeros, so the result is the
// dense one bit for bit, but columns that share no non-zero no longer wait on each other's
// square root and division (a tree's branches factor in parallel in the pipeline). The
// skipped entries of L are neither written nor read.
template <int N, typename T>
bool CholeskyFactorFixed(const MatrixX<T>& M, const char* nz, const char* constant, T* u,
                         T* inv_diag) {
  using std::sqrt;
  const T* m = M.data();
  auto L = [u](int i, int k) -> T& { return u[i * N + k]; };
  for (int j = 0; j < N; ++j) {
    // A column that follows from constant entries of M alone was factored by Build() and
    // written into u and inv_diag by Data's constructor (constant_mass.h).
    if (constant != nullptr && constant[j]) continue;
    T d = m[j + j * N];
    for (int k = 0; k < j; ++k)
      if (nz[j + k * N]) d = Sub(d, Mul(L(j, k), L(j, k)));
    if (!(ValueOf(d) > 0.0)) return false;
    inv_diag[j] = T(1.0) / sqrt(d);
    for (int i = j + 1; i < N; ++i) {
      if (!nz[i + j * N]) continue;
      T s = m[i + j * N];
      for (int k = 0; k < j; ++k)
        if (nz[i + k * N] && nz[j + k * N]) s = Sub(s, Mul(L(i, k), L(j, k)));
      L(i, j) = Mul(s, inv_diag[j]);
    }
  }
  return true;
}

template <int N, typename T>
void CholeskySolveFixed(const char* nz, const T* u, const T* inv_diag, const VectorX<T>& b,
                        VectorX<T>& y) {
  auto L = [u](int i, int k) -> const T& { return u[i * N + k]; };
  T* yv = y.data();
  for (int i = 0; i < N; ++i) {
    T s = b(i);
    for (int k = 0; k < i; ++k)
      if (nz[i + k * N]) s = Sub(s, Mul(L(i, k), yv[k]));
    yv[i] = Mul(s, inv_diag[i]);
  }
  for (int i = N - 1; i >= 0; --i) {
    T s = yv[i];
    for (int k = i + 1; k < N; ++k)
      if (nz[k + i * N]) s = Sub(s, Mul(L(k, i), yv[k]));
    yv[i] = Mul(s, inv_diag[i]);
  }
}

// The sparse factorisation P M Pᵀ = L Lᵀ of the model's plan (row-oriented, L's rows stored
// contiguously as the columns of `U`, whose structural zeros stay zero from Data's constructor
// so the inner products may run over the other row's non-zeros alone).
template <typename T>
bool SparseCholeskyFactor(const SparseFactorPlan& plan, const MatrixX<T>& M, MatrixX<T>& U,
                          VectorX<T>& inv_diag) {
  using std::sqrt;
  const int n = static_cast<int>(M.rows());
  const int last = n - 1;
  auto perm = [&](int i) { return plan.reversed ? last - i : i; };
  const T* m = M.data();
  T* u = U.data();
  T* id = inv_diag.data();
  const int* start = plan.row_start.data();
  const int* cols = plan.columns.data();
  for (int i = 0; i < n; ++i) {
    T* li = u + static_cast<Eigen::Index>(i) * n;  // L(i, 0..i)
    const int pi = perm(i);
    T d = m[pi + static_cast<Eigen::Index>(pi) * n];
    for (int a = start[i]; a < start[i + 1]; ++a) {
      const int k = cols[a];
      const T* lk = u + static_cast<Eigen::Index>(k) * n;
      T s = m[pi + static_cast<Eigen::Index>(perm(k)) * n];
      for (int c = start[k]; c < start[k + 1]; ++c) s = Sub(s, Mul(li[cols[c]], lk[cols[c]]));
      li[k] = Mul(s, id[k]);
      d = Sub(d, Mul(li[k], li[k]));
    }
    if (!(ValueOf(d) > 0.0)) return false;
    id[i] = T(1.0) / sqrt(d);
  }
  return true;
}

// L z = P b, then Lᵀ w = z (in place), then y = Pᵀ w.
template <typename T>
void SparseCholeskySolve(const SparseFactorPlan& plan, const MatrixX<T>& U,
                         const VectorX<T>& inv_diag, VectorX<T>& work, const VectorX<T>& b,
                         VectorX<T>& y) {
  const int n = static_cast<int>(U.rows());
  const int last = n - 1;
  auto perm = [&](int i) { return plan.reversed ? last - i : i; };
  const T* u = U.data();
  const T* id = inv_diag.data();
  const int* start = plan.row_start.data();
  const int* cols = plan.columns.data();
  T* z = work.data();
  for (int i = 0; i < n; ++i) {
    const T* li = u + static_cast<Eigen::Index>(i) * n;
    T s = b(perm(i));
    for (int a = start[i]; a < start[i + 1]; ++a) s = Sub(s, Mul(li[cols[a]], z[cols[a]]));
    z[i] = Mul(s, id[i]);
  }
  for (int i = last; i >= 0; --i) {
    const T* li = u + static_cast<Eigen::Index>(i) * n;
    z[i] = Mul(z[i], id[i]);
    for (int a = start[i]; a < start[i + 1]; ++a)
      z[cols[a]] = Sub(z[cols[a]], Mul(li[cols[a]], z[i]));
  }
  for (int i = 0; i < n; ++i) y(perm(i)) = z[i];
}

// From this size on, doubles use Eigen's blocked, vectorised in-place LLT (no allocation: the
// factor goes to data.cholesky_factor); below it the unblocked loop is cheaper.
constexpr int kBlockedCholeskyMin = 24;

template <typename T>
bool UsesBlocked(const Model& model, const Data<T>& data) {
  return std::is_same_v<T, double> && !model.sparse_factor() && data.n >= kBlockedCholeskyMin;
}

}  // namespace

template <typename T>
bool FactorMassMatrix(const Model& model, Data<T>& data) {
  // The constant columns below are the plan's (a Data copied, or last used with another model).
  if constexpr (std::is_same_v<T, double>) PlanFor(model, data);
  if (model.sparse_factor()) {
    return SparseCholeskyFactor(model.sparse_factor_plan(), data.M, data.cholesky_factor,
                                data.factor_inv_diag);
  }
  if constexpr (std::is_same_v<T, double>) {
    if (UsesBlocked(model, data)) {
      data.cholesky_factor.template triangularView<Eigen::Lower>() = data.M;
      const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(data.cholesky_factor);
      return llt.info() == Eigen::Success;
    }
  }
  const char* nz = model.factor_pattern().data();
  T* u = data.cholesky_factor.data();
  T* id = data.factor_inv_diag.data();
  // Doubles skip the constant columns; AutoDiff factors them (the same values) so that their
  // derivatives, exact zeros, are written too.
  const std::vector<char>& constant_columns = model.constant_mass().factor_column;
  const char* cc = std::is_same_v<T, double> && !constant_columns.empty()
                       ? constant_columns.data() : nullptr;
  switch (data.n) {
    case 1: return CholeskyFactorFixed<1>(data.M, nz, cc, u, id);
    case 2: return CholeskyFactorFixed<2>(data.M, nz, cc, u, id);
    case 3: return CholeskyFactorFixed<3>(data.M, nz, cc, u, id);
    case 4: return CholeskyFactorFixed<4>(data.M, nz, cc, u, id);
    case 5: return CholeskyFactorFixed<5>(data.M, nz, cc, u, id);
    case 6: return CholeskyFactorFixed<6>(data.M, nz, cc, u, id);
    default: return CholeskyFactor(data.M, data.cholesky_factor, data.factor_inv_diag);
  }
}

template <typename T>
void SolveFactoredMassMatrix(const Model& model, Data<T>& data) {
  if (model.sparse_factor()) {
    SparseCholeskySolve(model.sparse_factor_plan(), data.cholesky_factor, data.factor_inv_diag,
                        data.factor_work, data.g, data.udot);
    return;
  }
  if constexpr (std::is_same_v<T, double>) {
    if (UsesBlocked(model, data)) {
      // LLT::solveInPlace's two triangular solves on the factor FactorMassMatrix left.
      data.udot = data.g;
      data.cholesky_factor.template triangularView<Eigen::Lower>().solveInPlace(data.udot);
      data.cholesky_factor.adjoint().template triangularView<Eigen::Upper>().solveInPlace(
          data.udot);
      return;
    }
  }
  const char* nz = model.factor_pattern().data();
  const T* u = data.cholesky_factor.data();
  const T* id = data.factor_inv_diag.data();
  switch (data.n) {
    case 1: CholeskySolveFixed<1>(nz, u, id, data.g, data.udot); break;
    case 2: CholeskySolveFixed<2>(nz, u, id, data.g, data.udot); break;
    case 3: CholeskySolveFixed<3>(nz, u, id, data.g, data.udot); break;
    case 4: CholeskySolveFixed<4>(nz, u, id, data.g, data.udot); break;
    case 5: CholeskySolveFixed<5>(nz, u, id, data.g, data.udot); break;
    case 6: CholeskySolveFixed<6>(nz, u, id, data.g, data.udot); break;
    default: CholeskySolve(data.cholesky_factor, data.factor_inv_diag, data.g, data.udot);
  }
}

template bool FactorMassMatrix<double>(const Model&, Data<double>&);
template bool FactorMassMatrix<AutoDiff>(const Model&, Data<AutoDiff>&);
template void SolveFactoredMassMatrix<double>(const Model&, Data<double>&);
template void SolveFactoredMassMatrix<AutoDiff>(const Model&, Data<AutoDiff>&);

}  // namespace hybridtest::multibody::internal
