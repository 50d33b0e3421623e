#pragma once
// The Kane engine: numeric Kane's method over a Model, evaluated into a Data<T> workspace.
//
// With partial velocities v_j = ∂v/∂u_j and partial angular velocities ω_j = ∂ω/∂u_j, and the
// remainder accelerations a_rem, α_rem (the accelerations with u̇ = 0), Kane's equations
// Fr + Fr* = 0 (the paper's Eq. 16) become M u̇ = g with
//
//   M_jk = Σ_particles m v_j·v_k + Σ_bodies ( m v_G,j·v_G,k + ω_j·I ω_k )
//   g_j  = Σ_points  v_j·( F − m a_rem ) + Σ_frames ω_j·( T − I α_rem − ω × I ω )
//
// This is SymPy's convention (KanesMethod: mass_matrix · u̇ = forcing), M symmetric positive
// definite. The paper's Eq. (18) writes M ẋ + g = 0 with M negative; convert at the boundary
// with PaperFormFromKane() (paper_form.h). The state is x = [q; u; z] (2n + nz; z the extra
// first-order states of ModelBuilder::AddExtraState, often none), and
//
//   ẋ = f_rhs(t, x, r) = [ W(q) u ; M(q)⁻¹ g(t, q, u, z, r) ; f_z(t, q, u, z) ]
//                                                                    (the paper's Eq. 21 + z)
//
// r are the static restoring forces r^s [N], one per restoring-force slot. g is affine in r;
// the coupling matrix B = ∂g/∂r (n × num_slots) is exact (forward-mode AutoDiff).
//
// Every Calc* is templated on the scalar T ∈ {double, AutoDiff} and allocates nothing.
#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody {

// Kinematics at (t, x): rotations, angular velocities and accelerations, positions,
// velocities, partial velocities and remainder accelerations. x = [q; u; z] (2n + nz).
template <typename T>
void CalcKinematics(const Model& model, Data<T>& data, const T& t,
                    const Eigen::Ref<const VectorX<T>>& x);

// data.M from the last CalcKinematics. A tree of joints with q̇ = u (Model::tree_mass_matrix())
// takes the composite path, O(n·depth) (decision 0012); any other model the pairwise sum over
// each mass element's active speeds, O(Σ |active|²).
template <typename T>
void CalcMassMatrix(const Model& model, Data<T>& data);

// data.M by the pairwise sum, whatever the model (the general path; tests cross-check the
// tree path against it).
template <typename T>
void CalcMassMatrixPairwise(const Model& model, Data<T>& data);

// data.g from the last CalcKinematics and the restoring forces r (num_slots) [N].
template <typename T>
void CalcForcing(const Model& model, Data<T>& data, const Eigen::Ref<const VectorX<T>>& r);

// ẋ = f_rhs(t, x, r) (2n + nz): kinematics, M, g, Cholesky solve, then ż. Throws ModelError if M is not
// positive definite at x (e.g. a singular configuration of the user's coordinates). Without
// constraints and off the tree path, the points' p_OP and v_NP are not kept up to date (ẋ
// does not need them; CalcKinematics computes them).
template <typename T>
void CalcStateDerivative(const Model& model, Data<T>& data, const T& t,
                         const Eigen::Ref<const VectorX<T>>& x,
                         const Eigen::Ref<const VectorX<T>>& r, Eigen::Ref<VectorX<T>> xdot);

// The displacement each restoring-force slot's substructure sees, d_i(q, t) (num_slots).
// Unit: [m] (or [rad] for a rotational slot). Uses only data's scratch space.
template <typename T>
void CalcSlotDisplacements(const Model& model, Data<T>& data, const T& t,
                           const Eigen::Ref<const VectorX<T>>& q, Eigen::Ref<VectorX<T>> d);

// B = ∂g/∂r (n × num_slots) at (t, x): the generalized force of a unit restoring force in each
// slot (the hybrid coupling matrix). Exact. Allocates a workspace per call; the
// allocation-free form with a DerivativeWorkspace is in derivatives.h.
Eigen::MatrixXd CalcCouplingMatrix(const Model& model, double t, const Eigen::VectorXd& x);

// J = ∂f_rhs/∂x (nx × nx, nx = 2n + nz) at (t, x, r), exact. Allocates a workspace per call; the
// allocation-free form with a DerivativeWorkspace is in derivatives.h.
Eigen::MatrixXd CalcStateJacobian(const Model& model, double t, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& r);

namespace internal {
// CalcKinematics; with `positions` false, the points' positions p_OP and velocities v_NP, which
// ẋ needs only on the tree path (Model::tree_mass_matrix()) or with constraints, are not kept
// up to date (an affine point skips them, another one builds on its origin's stale values);
// everything else is computed, with the same values. CalcStateDerivative's unconstrained path
// passes model.tree_mass_matrix().
template <typename T>
void CalcKinematics(const Model& model, Data<T>& data, const T& t,
                    const Eigen::Ref<const VectorX<T>>& x, bool positions);

// ż = f_z(t, q, u, z) (nz; the loads' inputs with r left out) at the state of the last
// CalcKinematics, into data.zdot and the tail of xdot. Shared by the tree and constrained paths.
template <typename T>
void CalcExtraStateRates(const Model& model, Data<T>& data, Eigen::Ref<VectorX<T>> xdot);

// The model's compiled right-hand side (Model::compiled_rhs(), non-null) at (t, x, r): data.t,
// q, u, z and r set, data.M, g, qdot and zdot computed, and for a constrained model
// data.constraint_B, _velocity, _position and _bias (what CalcConstraints computes). Shared by
// the tree and constrained paths of CalcStateDerivative.
void CalcCompiledRhs(const Model& model, Data<double>& data, double t,
                     const Eigen::Ref<const VectorX<double>>& x,
                     const Eigen::Ref<const VectorX<double>>& r);
}  // namespace internal

}  // namespace hybridtest::multibody
