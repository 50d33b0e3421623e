// Kane's equations: mass matrix, forcing, state derivative, and exact derivatives through
// AutoDiff. See kane.h for the equations.
#include "hybridtest/multibody/kane.h"

#include <Eigen/Cholesky>
#include <fmt/core.h>

#include <algorithm>
#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/field_eval.h"
#include "hybridtest/multibody/planar_kinematics.h"
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
  internal::ZeroN(M.size(), m);
  // Translational inertia: m v_j·v_k, one precomputed term per pair j ≤ k (both triangles).
  for (const MassTerm& term : model.mass_terms()) {
    const T* v = data.v_partial[term.point].data();
    const T* vj = v + term.vj;
    const T* vk = v + term.vk;
    const T value = term.mass * (vj[0] * vk[0] + vj[1] * vk[1] + vj[2] * vk[2]);
    m[term.m_jk] += value;
    if (term.j != term.k) m[term.m_kj] += value;
  }
  const int planar = model.planar_axis();
  for (const RigidBodySpec& body : model.bodies()) {
    const std::vector<int>& active = model.compiled_frames()[body.frame].active;
    if constexpr (std::is_same_v<T, double>) {
      if (planar >= 0) {
        // Every ω_j is w_j e_A in N and in the body (R's row and column A are e_A), so
        // ω_j·I ω_k = w_k (I_AA w_j): the general terms below with their exact zeros left out.
        const double* W = data.w_partial[body.frame].data();
        const double I_AA = body.inertia(planar, planar);
        for (std::size_t a = 0; a < active.size(); ++a) {
          const double Iw = I_AA * W[3 * active[a] + planar];
          for (std::size_t b = a; b < active.size(); ++b) {
            const double value = W[3 * active[b] + planar] * Iw;
            M(active[a], active[b]) += value;
            if (b != a) M(active[b], active[a]) += value;
          }
        }
        continue;
      }
    }
    // Rotational inertia: ω_j·I ω_k, evaluated in body components (ω_B = Rᵀ ω_N), which
    // avoids forming I_N = R I Rᵀ. The partial angular velocities of the active speeds are
    // rotated once, into the 3 × n scratch.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const Matrix3X<T>& Wp = data.w_partial[body.frame];
    Matrix3X<T>& Wb = data.partial_rate3;
    for (int j : active) Wb.col(j) = internal::TransposeMultiply(R, Vector3<T>(Wp.col(j)));
    for (std::size_t a = 0; a < active.size(); ++a) {
      const Vector3<T> Iw = internal::InertiaTimes(body.inertia, Vector3<T>(Wb.col(active[a])));
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
  const int planar = model.planar_axis();  // doubles skip the planar structural zeros
  if (r.size() != model.num_slots()) {
    throw ModelError(fmt::format("expected {} restoring forces (one per slot), got {}",
                                 model.num_slots(), r.size()));
  }
  internal::CopyN(r.data(), r.size(), data.r.data());  // plain copy: r is contiguous
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
    const Vector3<T> value = load.function.template get<T>()(args);
    T* sum = (load.kind == LoadSpec::Kind::kForce ? data.force : data.torque)[load.target].data();
    if (load.expressed_in == 0) {
      for (int c = 0; c < 3; ++c) sum[c] = internal::Add(sum[c], value(c));
      continue;
    }
    const Matrix3<T>& R = data.R_NF[load.expressed_in];
    if constexpr (std::is_same_v<T, double>) {
      if (planar >= 0) {
        // Into a separate array, element by element: a copy of the returned vector is read
        // with one wide load over the callee's narrow stores, which stalls.
        double rotated[3];
        internal::RotatePlanar(planar, R.data(), value.data(), rotated);
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + rotated[c];
        continue;
      }
    }
    const Vector3<T> rotated = internal::Multiply(R, value);
    for (int c = 0; c < 3; ++c) sum[c] = internal::Add(sum[c], rotated(c));
  }
  // Inertia forces and torques (remainder parts: the u̇ parts are in M).
  auto subtract_inertia_force = [&](int point, double mass) {
    T* f = data.force[point].data();
    const T* a = data.a_rem[point].data();
    for (int c = 0; c < 3; ++c) f[c] = internal::Sub(f[c], internal::Scale(mass, a[c]));
  };
  for (const ParticleSpec& p : model.particles()) subtract_inertia_force(p.point, p.mass);
  for (const RigidBodySpec& body : model.bodies()) {
    if (body.mass > 0.0) subtract_inertia_force(body.mass_center, body.mass);
    if constexpr (std::is_same_v<T, double>) {
      if (planar >= 0) {
        internal::SubtractPlanarInertiaTorque(planar, body, data);
        continue;
      }
    }
    // I α + ω × I ω in body components, back to N.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const Vector3<T> w_B = internal::TransposeMultiply(R, data.w_NF[body.frame]);
    const Vector3<T> alpha_B = internal::TransposeMultiply(R, data.alpha_rem[body.frame]);
    const Vector3<T> I_w = internal::InertiaTimes(body.inertia, w_B);
    const Vector3<T> I_alpha = internal::InertiaTimes(body.inertia, alpha_B);
    Vector3<T> gyro;
    internal::Cross(w_B.data(), I_w.data(), gyro.data());
    const Vector3<T> torque = internal::Multiply(R, Vector3<T>(I_alpha + gyro));
    T* sum = data.torque[body.frame].data();
    for (int c = 0; c < 3; ++c) sum[c] = internal::Sub(sum[c], torque(c));
  }
  // Projection onto the partial velocities (Kane's generalized forces).
  T* g = data.g.data();
  internal::ZeroN(n, g);
  for (int p : model.loaded_points()) {
    const T* V = data.v_partial[p].data();
    const T* f = data.force[p].data();
    for (int j : model.compiled_points()[p].active)
      g[j] = internal::Add(g[j], internal::Dot(V + 3 * j, f));
  }
  for (int f : model.loaded_frames()) {
    const T* W = data.w_partial[f].data();
    const T* tau = data.torque[f].data();
    for (int j : model.compiled_frames()[f].active)
      g[j] = internal::Add(g[j], internal::Dot(W + 3 * j, tau));
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

// The same factorisation for a compile-time size N (the loops unroll; L lives on the stack),
// skipping the structural zeros of L (`nz`, Model::factor_pattern()): the terms it skips are
// exact zeros, so the result is the dense one bit for bit, but columns that share no non-zero
// no longer wait on each other's square root and division (a tree's branches factor in
// parallel in the pipeline).
template <int N, typename T>
bool CholeskySolveFixed(const MatrixX<T>& M, const char* nz, const VectorX<T>& b, VectorX<T>& y) {
  using std::sqrt;
  const T* m = M.data();
  T L[N][N];  // row i holds L(i, 0..i)
  T inv_diag[N];
  for (int j = 0; j < N; ++j) {
    T d = m[j + j * N];
    for (int k = 0; k < j; ++k)
      if (nz[j + k * N]) d = internal::Sub(d, internal::Mul(L[j][k], L[j][k]));
    if (!(ValueOf(d) > 0.0)) return false;
    inv_diag[j] = T(1.0) / sqrt(d);
    for (int i = j + 1; i < N; ++i) {
      if (!nz[i + j * N]) continue;
      T s = m[i + j * N];
      for (int k = 0; k < j; ++k)
        if (nz[i + k * N] && nz[j + k * N]) s = internal::Sub(s, internal::Mul(L[i][k], L[j][k]));
      L[i][j] = internal::Mul(s, inv_diag[j]);
    }
  }
  T* yv = y.data();
  for (int i = 0; i < N; ++i) {
    T s = b(i);
    for (int k = 0; k < i; ++k)
      if (nz[i + k * N]) s = internal::Sub(s, internal::Mul(L[i][k], yv[k]));
    yv[i] = internal::Mul(s, inv_diag[i]);
  }
  for (int i = N - 1; i >= 0; --i) {
    T s = yv[i];
    for (int k = i + 1; k < N; ++k)
      if (nz[k + i * N]) s = internal::Sub(s, internal::Mul(L[k][i], yv[k]));
    yv[i] = internal::Mul(s, inv_diag[i]);
  }
  return true;
}

// M y = b by the sparse factorisation P M Pᵀ = L Lᵀ of the model's plan (row-oriented, L's
// rows stored contiguously as the columns of `U`, whose structural zeros stay zero from Data's
// constructor so the inner products may run over the other row's non-zeros alone).
template <typename T>
bool SparseCholeskySolve(const SparseFactorPlan& plan, const MatrixX<T>& M, MatrixX<T>& U,
                         VectorX<T>& inv_diag, VectorX<T>& work, const VectorX<T>& b,
                         VectorX<T>& y) {
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
      for (int c = start[k]; c < start[k + 1]; ++c)
        s = internal::Sub(s, internal::Mul(li[cols[c]], lk[cols[c]]));
      li[k] = internal::Mul(s, id[k]);
      d = internal::Sub(d, internal::Mul(li[k], li[k]));
    }
    if (!(ValueOf(d) > 0.0)) return false;
    id[i] = T(1.0) / sqrt(d);
  }
  // L z = P b, then Lᵀ w = z (in place), then y = Pᵀ w.
  T* z = work.data();
  for (int i = 0; i < n; ++i) {
    const T* li = u + static_cast<Eigen::Index>(i) * n;
    T s = b(perm(i));
    for (int a = start[i]; a < start[i + 1]; ++a)
      s = internal::Sub(s, internal::Mul(li[cols[a]], z[cols[a]]));
    z[i] = internal::Mul(s, id[i]);
  }
  for (int i = last; i >= 0; --i) {
    const T* li = u + static_cast<Eigen::Index>(i) * n;
    z[i] = internal::Mul(z[i], id[i]);
    for (int a = start[i]; a < start[i + 1]; ++a)
      z[cols[a]] = internal::Sub(z[cols[a]], internal::Mul(li[cols[a]], z[i]));
  }
  for (int i = 0; i < n; ++i) y(perm(i)) = z[i];
  return true;
}

// From this size on, doubles use Eigen's blocked, vectorised in-place LLT (no allocation: the
// factor goes to data.cholesky_factor); below it the unblocked loop is cheaper.
constexpr int kBlockedCholeskyMin = 24;

// M y = g: unrolled for the small sizes of typical models, the dynamic loop for medium ones,
// Eigen's blocked LLT for large ones (doubles).
template <typename T>
bool SolveMassMatrix(const Model& model, Data<T>& data) {
  const char* nz = model.factor_pattern().data();
  if (model.sparse_factor()) {
    return SparseCholeskySolve(model.sparse_factor_plan(), data.M, data.cholesky_factor,
                               data.partial_rate, data.factor_work, data.g, data.udot);
  }
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
    case 1: return CholeskySolveFixed<1>(data.M, nz, data.g, data.udot);
    case 2: return CholeskySolveFixed<2>(data.M, nz, data.g, data.udot);
    case 3: return CholeskySolveFixed<3>(data.M, nz, data.g, data.udot);
    case 4: return CholeskySolveFixed<4>(data.M, nz, data.g, data.udot);
    case 5: return CholeskySolveFixed<5>(data.M, nz, data.g, data.udot);
    case 6: return CholeskySolveFixed<6>(data.M, nz, data.g, data.udot);
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
  if (!SolveMassMatrix(model, data)) {
    throw ModelError(fmt::format("the mass matrix is not positive definite at t = {} s: the "
                                 "generalized coordinates are singular there, or a mass or "
                                 "inertia is missing", ValueOf(t)));
  }
  internal::CopyN(data.qdot.data(), n, xdot.data());
  internal::CopyN(data.udot.data(), n, xdot.data() + n);
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
