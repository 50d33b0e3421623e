#pragma once
// Data<T>: the mutable workspace of the Kane engine for one Model (Pinocchio's Model/Data
// split). Everything is sized once, in the constructor: evaluating the equations of motion
// allocates nothing. Fields are the results of the last Calc* call (kane.h), in SI units,
// vectors expressed in the Newtonian frame N unless stated.
#include <cstdint>
#include <functional>
#include <vector>

#include "hybridtest/multibody/model.h"

namespace hybridtest::multibody {

namespace internal {
// What the evaluation of doubles precomputes for one model inside one Data<double>
// (kane.cc, planar_kinematics.cc):
// - for Model::grouped_sums(), per term the addresses of its two vectors in this Data, so that
//   the sums' loops load one pointer per operand instead of walking from the arrays' starts
//   through each matrix's own buffer;
// - per applied load, its function and the addresses of its resultant and of the rotation of
//   the frame it is expressed in (none for N);
// - for a planar model (Model::planar_axis() ≥ 0, q̇ = u), the rigid bodies' rotational terms
//   of M, which are constant there: every partial angular velocity is a sum of the angles'
//   constant coefficients (and Data::w_partial holds those constants, written here once).
// Data's constructor makes it; a Data that was copied or moved, or that is used with another
// model of the same shape (or with its model after that was assigned another), makes it again
// on its next evaluation (`owner`, `model_id`: Model::instance_id()), and then also writes that
// model's constant columns of M's factor (constant_mass.h) again.
struct EvaluationPlan {
  struct Mass {  // M(j, k) (and M(k, j)) += mass v_j·v_k (Model::grouped_mass_terms())
    const double* vj;
    const double* vk;
    double mass;  // [kg]
    int m_jk;
    int m_kj;
    bool continues;
  };
  struct Projection {  // g_j += v_j·F (or ω_j·τ) (Model::projection_terms())
    const double* partial;
    const double* load;
    int j;
    bool continues;
  };
  struct Load {  // resultant += R value (Model::loads(), in order)
    const std::function<LoadSignature<double>>* function;
    double* sum;               // Data::force or Data::torque of its target
    const Matrix3<double>* R;  // Data::R_NF of the frame it is expressed in; null for N
  };
  struct Rotation {  // M(j, k) += ω_j·I ω_k of one body (and M(k, j) if m_kj ≥ 0)
    int m_jk;
    int m_kj;  // −1 on the diagonal
    double value;  // [kg·m²]
  };
  const void* owner = nullptr;
  std::uint64_t model_id = 0;
  std::vector<Mass> mass;
  std::vector<Projection> projection;
  std::vector<Load> loads;
  std::vector<Rotation> planar_rotation;
};
}  // namespace internal

template <typename T>
struct Data {
  explicit Data(const Model& model);

  int n = 0;  // number of coordinates = number of speeds

  // State of the last CalcKinematics.
  T t{0.0};          // [s]
  VectorX<T> q;      // (n) generalized coordinates
  VectorX<T> u;      // (n) generalized speeds
  VectorX<T> z;      // (nz) extra first-order states (Model::extra_states())
  VectorX<T> qdot;   // (n) q̇ = W(q) u
  VectorX<T> qddot_rem;  // (n) q̈ with u̇ = 0, i.e. Ẇ u
  MatrixX<T> W;      // (n × n) kinematical matrix (identity unless the model says otherwise)

  // Frames, indexed like Model::frames().
  std::vector<Matrix3<T>> R_NF;        // rotation: F components → N components
  std::vector<Vector3<T>> w_NF;        // angular velocity of F in N [rad/s]
  std::vector<Matrix3X<T>> w_partial;  // (3 × n) partial angular velocities ∂ω/∂u_j
  std::vector<Vector3<T>> alpha_rem;   // angular acceleration with u̇ = 0 [rad/s²]

  // Points, indexed like Model::points().
  std::vector<Vector3<T>> p_OP;        // position from O [m]
  std::vector<Vector3<T>> v_NP;        // velocity in N [m/s]
  std::vector<Matrix3X<T>> v_partial;  // (3 × n) partial velocities ∂v/∂u_j
  std::vector<Vector3<T>> a_rem;       // acceleration with u̇ = 0 [m/s²]

  // Results.
  MatrixX<T> M;     // (n × n) mass matrix, symmetric positive definite
  VectorX<T> g;     // (n) forcing: M u̇ = g
  VectorX<T> udot;  // (n)
  VectorX<T> zdot;  // (nz) rates of the extra states
  VectorX<T> r;     // (num_slots) restoring forces of the last CalcForcing [N]
  std::vector<T> time_values;  // (num_time_functions) f_k(t) of the last CalcForcing

  // Scratch.
  std::vector<Vector3<T>> force;   // per point: resultant of loads and inertia forces [N]
  std::vector<Vector3<T>> torque;  // per frame: resultant torque [N·m]
  std::vector<Jet<T>> q_jets;      // (n) seeds for general kinematic expressions
  std::vector<Jet<T>> jet_buffer;  // (max(9, n·n))
  VectorX<T> partial_rate;         // (n)
  Matrix3X<T> partial_rate3;       // (3 × n)
  MatrixX<T> cholesky_factor;      // (n × n) Lᵀ of M = L Lᵀ (upper triangle used)
  VectorX<T> factor_work;          // (n) the sparse solve's permuted right-hand side
  VectorX<T> factor_inv_diag;      // (n) 1/L_ii of the factor
  internal::EvaluationPlan plan;  // doubles only
  // Tree mass matrix (Model::tree_mass_matrix()): per speed j, the joint axis (ω_j, v_j at O)
  // and the spatial momentum about O of everything u_j moves, per unit u_j.
  Matrix3X<T> joint_w;       // (3 × n) [rad/s per unit u_j]
  Matrix3X<T> joint_v;       // (3 × n) [m/s per unit u_j]
  Matrix3X<T> momentum_lin;  // (3 × n) [kg·m/s per unit u_j]
  Matrix3X<T> momentum_ang;  // (3 × n) [kg·m²/s per unit u_j]
  // Composite inertia, about O in N, of everything joint j moves: mass, first moment m p,
  // and rotational inertia about O.
  VectorX<T> composite_mass;                   // (n) [kg]
  Matrix3X<T> composite_moment;                // (3 × n) [kg·m]
  std::vector<Matrix3<T>> composite_inertia;   // (n) [kg·m²]

  // Constraints (Model::has_constraints(); empty otherwise), m = num_constraint_rows(),
  // p = n − m; constraints.h. Rows in the units of their constraint.
  MatrixX<T> constraint_B;         // (m × n) B(q, t) of B u + c = 0
  VectorX<T> constraint_velocity;  // (m) B u + c at the state
  VectorX<T> constraint_bias;      // (m) Ḃ u + ċ: B u̇ + bias = 0 are the acceleration constraints
  VectorX<T> constraint_position;  // (m) f(q, t) for holonomic rows, 0 for the others
  std::vector<int> dependent;      // (m) the dependent speeds of the last reduction
  std::vector<int> independent;    // (p) the others, ascending
  MatrixX<T> constraint_A;         // (m × p) u_dep = A u_ind + b: A = −B_dep⁻¹ B_ind
  MatrixX<T> reduced_M;            // (n × n) [Cᵀ M; B]: rows p independent, then m constraint
  VectorX<T> reduced_f;            // (n) [Cᵀ g; −bias − stabilisation]
  MatrixX<T> lu;                   // (n × n) LU factor scratch
  std::vector<int> lu_pivots;      // (n)
  Eigen::MatrixXd pivot_scratch;   // (m × n) values of B for the pivoted choice
};

namespace internal {
// Makes data.plan for `model` (no allocation when its sizes are already those of the model's
// terms) and, for a planar model, writes the constant partial angular velocities: called by
// Data's constructor and, through PlanFor, by the evaluation.
void MakeEvaluationPlan(const Model& model, Data<double>& data);
// data.plan, made again first if `data` was copied or moved or last used with another model.
inline const EvaluationPlan& PlanFor(const Model& model, Data<double>& data) {
  if (data.plan.owner != &data || data.plan.model_id != model.instance_id()) {
    MakeEvaluationPlan(model, data);
  }
  return data.plan;
}
}  // namespace internal

extern template struct Data<double>;
extern template struct Data<AutoDiff>;
extern template struct Data<Symbolic>;

}  // namespace hybridtest::multibody
