// Kane's equations: mass matrix, forcing, state derivative, and exact derivatives through
// AutoDiff. See kane.h for the equations.
#include "hybridtest/multibody/kane.h"

#include <Eigen/Cholesky>
#include <fmt/core.h>

#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/tree_mass.h"

namespace hybridtest::multibody {

template <typename T>
void CalcMassMatrix(const Model& model, Data<T>& data) {
  if (model.tree_mass_matrix()) {
    internal::CalcTreeMassMatrix(model, data);
  } else {
    CalcMassMatrixPairwise(model, data);
  }
}

template <typename T>
void CalcMassMatrixPairwise(const Model& model, Data<T>& data) {
  MatrixX<T>& M = data.M;
  T* m = M.data();  // column-major: M(j, k) = m[j + k n] (offsets in MassTerm)
  M.setZero();
  // Translational inertia: m v_j·v_k, one precomputed term per pair j ≤ k (both triangles).
  for (const MassTerm& term : model.mass_terms()) {
    const T* v = data.v_partial[term.point].data();
    const T* vj = v + term.vj;
    const T* vk = v + term.vk;
    const T value = term.mass * (vj[0] * vk[0] + vj[1] * vk[1] + vj[2] * vk[2]);
    m[term.m_jk] += value;
    if (term.j != term.k) m[term.m_kj] += value;
  }
  for (const RigidBodySpec& body : model.bodies()) {
    // Rotational inertia: ω_j·I ω_k, evaluated in body components (ω_B = Rᵀ ω_N), which
    // avoids forming I_N = R I Rᵀ. The partial angular velocities of the active speeds are
    // rotated once, into the 3 × n scratch.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const std::vector<int>& active = model.frames()[body.frame].active;
    const Matrix3X<T>& Wp = data.w_partial[body.frame];
    Matrix3X<T>& Wb = data.partial_rate3;
    for (int j : active) Wb.col(j).noalias() = R.transpose() * Wp.col(j);
    for (std::size_t a = 0; a < active.size(); ++a) {
      const Vector3<T> Iw = body.inertia.template cast<T>() * Wb.col(active[a]);
      for (std::size_t b = a; b < active.size(); ++b) {
        const T value = Wb.col(active[b]).dot(Iw);
        M(active[a], active[b]) += value;
        if (b != a) M(active[b], active[a]) += value;
      }
    }
  }
}

template <typename T>
void CalcForcing(const Model& model, Data<T>& data, const Eigen::Ref<const VectorX<T>>& r) {
  const int n = data.n;
  if (r.size() != model.num_slots()) {
    throw ModelError(fmt::format("expected {} restoring forces (one per slot), got {}",
                                 model.num_slots(), r.size()));
  }
  data.r = r;
  for (int p : model.loaded_points()) data.force[p].setZero();
  for (int f : model.loaded_frames()) data.torque[f].setZero();
  // Time functions, once; then the applied loads, converted to N components.
  for (std::size_t k = 0; k < data.time_values.size(); ++k) {
    data.time_values[k] = model.time_functions()[k].function.template get<T>()(data.t);
  }
  const LoadArgs<T> args{data.t, std::span<const T>(data.q.data(), n),
                         std::span<const T>(data.u.data(), n),
                         std::span<const T>(data.r.data(), data.r.size()),
                         std::span<const T>(data.time_values.data(), data.time_values.size()),
                         std::span<const T>(data.z.data(), data.z.size())};
  for (const LoadSpec& load : model.loads()) {
    Vector3<T> value = load.function.template get<T>()(args);
    if (load.expressed_in != 0) value = data.R_NF[load.expressed_in] * value;
    (load.kind == LoadSpec::Kind::kForce ? data.force : data.torque)[load.target] += value;
  }
  // Inertia forces and torques (remainder parts: the u̇ parts are in M).
  for (const ParticleSpec& p : model.particles()) data.force[p.point] -= p.mass * data.a_rem[p.point];
  for (const RigidBodySpec& body : model.bodies()) {
    if (body.mass > 0.0) data.force[body.mass_center] -= body.mass * data.a_rem[body.mass_center];
    // I α + ω × I ω in body components, back to N.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const Matrix3<double>& I = body.inertia;
    const Vector3<T> w_B = R.transpose() * data.w_NF[body.frame];
    const Vector3<T> alpha_B = R.transpose() * data.alpha_rem[body.frame];
    const Vector3<T> I_w = I.template cast<T>() * w_B;
    data.torque[body.frame] -= R * (I.template cast<T>() * alpha_B + w_B.cross(I_w));
  }
  // Projection onto the partial velocities (Kane's generalized forces).
  data.g.setZero();
  for (int p : model.loaded_points()) {
    for (int j : model.points()[p].active) data.g(j) += data.v_partial[p].col(j).dot(data.force[p]);
  }
  for (int f : model.loaded_frames()) {
    for (int j : model.frames()[f].active) data.g(j) += data.w_partial[f].col(j).dot(data.torque[f]);
  }
}

namespace {
// Solves M y = b by an unblocked Cholesky factorisation M = L Lᵀ, reading M's lower triangle
// only and never writing M: Lᵀ goes to `U` (n × n, column-major, so row i of L is the
// contiguous column i of U) and 1/L_jj to `inv_diag` (n). Raw column-major indexing: for the
// small n of a multibody model this is several times cheaper than Eigen's dynamic-size LLT
// and triangular solves, and allocates nothing. Returns false if M is not positive definite
// (y is then unspecified).
template <typename T>
bool CholeskySolve(const MatrixX<T>& M, MatrixX<T>& U, VectorX<T>& inv_diag, const VectorX<T>& b,
                   VectorX<T>& y) {
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
  // L z = b, then Lᵀ y = z (z stored in y).
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
  return true;
}

// The same factorisation for a compile-time size N (the loops unroll; L lives on the stack).
template <int N, typename T>
bool CholeskySolveFixed(const MatrixX<T>& M, const VectorX<T>& b, VectorX<T>& y) {
  using std::sqrt;
  const T* m = M.data();
  T L[N][N];  // row i holds L(i, 0..i)
  T inv_diag[N];
  for (int j = 0; j < N; ++j) {
    T d = m[j + j * N];
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(ValueOf(d) > 0.0)) return false;
    inv_diag[j] = T(1.0) / sqrt(d);
    for (int i = j + 1; i < N; ++i) {
      T s = m[i + j * N];
      for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = s * inv_diag[j];
    }
  }
  T* yv = y.data();
  for (int i = 0; i < N; ++i) {
    T s = b(i);
    for (int k = 0; k < i; ++k) s -= L[i][k] * yv[k];
    yv[i] = s * inv_diag[i];
  }
  for (int i = N - 1; i >= 0; --i) {
    T s = yv[i];
    for (int k = i + 1; k < N; ++k) s -= L[k][i] * yv[k];
    yv[i] = s * inv_diag[i];
  }
  return true;
}

// From this size on, doubles use Eigen's blocked, vectorised in-place LLT (no allocation: the
// factor goes to data.cholesky_factor); below it the unblocked loop is cheaper.
constexpr int kBlockedCholeskyMin = 24;

// M y = g: unrolled for the small sizes of typical models, the dynamic loop for medium ones,
// Eigen's blocked LLT for large ones (doubles).
template <typename T>
bool SolveMassMatrix(Data<T>& data) {
  if constexpr (std::is_same_v<T, double>) {
    if (data.n >= kBlockedCholeskyMin) {
      data.cholesky_factor.template triangularView<Eigen::Lower>() = data.M;
      const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(data.cholesky_factor);
      if (llt.info() != Eigen::Success) return false;
      data.udot = data.g;
      llt.solveInPlace(data.udot);
      return true;
    }
  }
  switch (data.n) {
    case 1: return CholeskySolveFixed<1>(data.M, data.g, data.udot);
    case 2: return CholeskySolveFixed<2>(data.M, data.g, data.udot);
    case 3: return CholeskySolveFixed<3>(data.M, data.g, data.udot);
    case 4: return CholeskySolveFixed<4>(data.M, data.g, data.udot);
    case 5: return CholeskySolveFixed<5>(data.M, data.g, data.udot);
    case 6: return CholeskySolveFixed<6>(data.M, data.g, data.udot);
    default:
      return CholeskySolve(data.M, data.cholesky_factor, data.partial_rate, data.g, data.udot);
  }
}
}  // namespace

template <typename T>
void CalcStateDerivative(const Model& model, Data<T>& data, const T& t,
                         const Eigen::Ref<const VectorX<T>>& x,
                         const Eigen::Ref<const VectorX<T>>& r, Eigen::Ref<VectorX<T>> xdot) {
  const int n = data.n;
  if (xdot.size() != model.num_states()) {
    throw ModelError(fmt::format("ẋ has {} entries; expected 2n + nz = {}", xdot.size(),
                                 model.num_states()));
  }
  CalcKinematics(model, data, t, x);
  CalcMassMatrix(model, data);
  CalcForcing(model, data, r);
  if (!SolveMassMatrix(data)) {
    throw ModelError(fmt::format("the mass matrix is not positive definite at t = {} s: the "
                                 "generalized coordinates are singular there, or a mass or "
                                 "inertia is missing", ValueOf(t)));
  }
  xdot.head(n) = data.qdot;
  xdot.segment(n, n) = data.udot;
  if (model.num_extra_states() > 0) {
    // ż = f_z(t, q, u, z): the loads' inputs with r left out.
    const LoadArgs<T> args{data.t, std::span<const T>(data.q.data(), n),
                           std::span<const T>(data.u.data(), n), std::span<const T>(),
                           std::span<const T>(data.time_values.data(), data.time_values.size()),
                           std::span<const T>(data.z.data(), data.z.size())};
    for (int k = 0; k < model.num_extra_states(); ++k) {
      data.zdot(k) = model.extra_states()[k].rate.template get<T>()(args);
    }
    xdot.tail(model.num_extra_states()) = data.zdot;
  }
}

#define HYBRIDTEST_INSTANTIATE(T)                                                             \
  template void CalcMassMatrix<T>(const Model&, Data<T>&);                                    \
  template void CalcMassMatrixPairwise<T>(const Model&, Data<T>&);                            \
  template void CalcForcing<T>(const Model&, Data<T>&, const Eigen::Ref<const VectorX<T>>&);  \
  template void CalcStateDerivative<T>(const Model&, Data<T>&, const T&,                      \
                                       const Eigen::Ref<const VectorX<T>>&,                   \
                                       const Eigen::Ref<const VectorX<T>>&,                   \
                                       Eigen::Ref<VectorX<T>>);
HYBRIDTEST_INSTANTIATE(double)
HYBRIDTEST_INSTANTIATE(AutoDiff)
#undef HYBRIDTEST_INSTANTIATE

}  // namespace hybridtest::multibody
