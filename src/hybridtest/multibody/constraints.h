#pragma once
// Constrained Kane's equations (constraint_spec.h declares the constraints).
//
// The m velocity constraints B(q, t) u + c(q, t) = 0 (holonomic rows: f(q, t) = 0
// differentiated once) split the speeds into p = n − m independent ones u_i and m dependent
// ones u_d (chosen by the user or by a completely pivoted elimination of B):
//
//   u_d = A u_i + b,   A = −B_d⁻¹ B_i,   b = −B_d⁻¹ c.
//
// With C the n × p matrix whose rows are I (independent speeds) and A (dependent speeds), the
// reduced equations Fr~ + Fr*~ = 0 (Kane and Levinson 1985, ch. 6; SymPy's KanesMethod with
// u_dependent and velocity_constraints) are Cᵀ (g − M u̇) = 0, with M and g the tree's own
// (kane.h). The acceleration constraints B u̇ + (Ḃ u + ċ) = 0 close them:
//
//   [ Cᵀ M ] u̇ = [ Cᵀ g            ]            (n × n; SymPy's mass_matrix and forcing,
//   [ B    ]      [ −(Ḃ u + ċ) − s ]             rows: independent speeds, then constraints)
//
// s is Baumgarte's stabilisation, 2α (B u + c) + α² f with α = 1/τ (f only for holonomic
// rows; ConstraintOptions::stabilisation_time_constant τ, 0: s = 0). It vanishes on the
// constraint manifold, so the equations there, their linearisation and their eigenvalues are
// the unstabilised ones; off it, it pulls the drift of a long run back with time constant τ.
// u̇ does not depend on which speeds are dependent (it solves M u̇ = g + Bᵀλ, B u̇ = −bias − s).
//
// The state stays x = [q; u; z] (2n + nz), so every integrator and scheme runs a constrained
// model unchanged; CalcStateDerivative (kane.h) takes this path when the model has
// constraints. Templated on T ∈ {double, AutoDiff}; CalcConstraints also on Symbolic.
#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody {

// data.constraint_B, _velocity, _bias and _position at the state of the last CalcKinematics.
template <typename T>
void CalcConstraints(const Model& model, Data<T>& data);

// The dependent speeds (data.dependent, data.independent): the user's
// (ConstraintOptions::dependent_speeds), else picked by complete pivoting of B's values.
// Returns false if B is rank-deficient (redundant or contradictory constraints at this state).
template <typename T>
bool ChooseDependentSpeeds(const Model& model, Data<T>& data);

// data.constraint_A, data.reduced_M and data.reduced_f (see above) from the last
// CalcConstraints, CalcMassMatrix and CalcForcing; `stabilise` adds s. Throws ModelError
// naming the dependent speeds if B_d is singular.
template <typename T>
void CalcReducedEquations(const Model& model, Data<T>& data, bool stabilise);

// ẋ of a constrained model (the path CalcStateDerivative takes): kinematics, M, g, the
// constraints, the reduced equations (stabilised) solved for u̇. Throws ModelError if the
// system is singular.
template <typename T>
void CalcConstrainedStateDerivative(const Model& model, Data<T>& data, const T& t,
                                    const Eigen::Ref<const VectorX<T>>& x,
                                    const Eigen::Ref<const VectorX<T>>& r,
                                    Eigen::Ref<VectorX<T>> xdot);

// ∂u̇/∂r (n × num_slots) of a constrained model from the coupling matrix B_r = ∂g/∂r (n ×
// num_slots, CalcCouplingMatrix) and the reduction of the last CalcStateDerivative on `data`:
// u̇ = R⁻¹ [Cᵀ g; −bias − s] with only g reading r, so ∂u̇/∂r = R⁻¹ [Cᵀ B_r; 0]. (For a tree,
// ∂u̇/∂r = M⁻¹ B_r.) `out` is overwritten; `data.lu` is refactored.
void CalcConstrainedRateCoupling(const Model& model, Data<double>& data,
                                 const Eigen::Ref<const Eigen::MatrixXd>& B_r,
                                 Eigen::Ref<Eigen::MatrixXd> out);

// The constraint forces at the state of the last CalcConstrainedStateDerivative on `data`: the
// multipliers λ (m, one per row of B u + c = 0) of M u̇ = g + Bᵀ λ, with M, g the tree's and u̇
// the constrained solution (the reduced rows Cᵀ (g − M u̇) = 0 put M u̇ − g in the range of
// Bᵀ). Solved from the dependent speeds' rows, B_dᵀ λ = (M u̇ − g)_d. Bᵀ λ is the generalized
// force the constraints apply, so a row of a "coincide: [P, Q]" constraint gives the force on
// P (and −λ on Q) along its component [N], a "velocity_zero" row the force on the body at P
// (the ground's contact force on a wheel) [N], an expression row the work per unit of the
// row (ConstraintSpec::force_unit). Allocation-free; `data.lu` is refactored. Throws
// ModelError if B_d is singular (as the derivative would have).
void CalcConstraintForces(const Model& model, Data<double>& data, Eigen::Ref<Eigen::VectorXd> lambda);

// Names of the rows of B u + c = 0, for messages: "loop (x)", "rear contact (y)".
std::string ConstraintRowName(const Model& model, int row);

}  // namespace hybridtest::multibody
