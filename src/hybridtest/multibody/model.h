#pragma once
// A multibody model for Kane's method: constant after Build() (Pinocchio's Model/Data split;
// the mutable workspace is Data<T>, data.h; the algorithms are free functions, kane.h).
//
// A model is a tree of frames (each oriented relative to a parent) and a tree of points (each
// located relative to another point), rooted at the Newtonian frame N and its origin O;
// particles and rigid bodies carry mass; forces act at points and torques on frames; and
// restoring-force slots name the hybrid unknowns r^s that loads may depend on.
//
// Coordinates q (n) and generalized speeds u (n) are related by the kinematical differential
// equations q̇ = W(q) u, W = identity unless SetKinematicalEquations() says otherwise. Extra
// first-order states z (nz, AddExtraState: a controller's integrator, a filter) follow them in
// the state x = [q; u; z] (2n + nz) with ż = f_z(t, q, u, z); loads may read z.
//
//   ModelBuilder b({{"q1", "m", "tip deflection"}, {"q2", "rad", "hub angle"}});
//   FrameId H = b.AddFrameAboutAxis("H", b.newtonian(), {0, 0, 1}, ScalarField::Coordinate(1));
//   PointId P = b.AddPoint("P", b.origin(), H, {ScalarField::Constant(0.5),
//                                               ScalarField::Coordinate(0), {}});
//   b.AddParticle("tip", P, 1.96);
//   int r1 = b.AddRestoringForceSlot("r1", "blade root force", ScalarField::Coordinate(0));
//   b.AddForce("spring", P, H, [](const auto& a) { using T = ...; return Vector3<T>(0, -a.r[0], 0); });
//   Model model = std::move(b).Build();
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/multibody/constant_mass.h"
#include "hybridtest/multibody/constraint_spec.h"
#include "hybridtest/multibody/kinematic_field.h"
#include "hybridtest/multibody/symbolic_compiled.h"

namespace hybridtest::multibody {

struct FrameId {
  int index = -1;
};
struct PointId {
  int index = -1;
};

// Name, unit and meaning of a generalized coordinate or speed, or of a slot.
struct QuantityInfo {
  std::string name;         // "q1"
  std::string unit;         // "m", "rad", "m/s", "rad/s", "N"
  std::string description;  // "tip deflection of blade 1"
};

// The specs below are what the user wrote (through ModelBuilder); Build() never writes into
// them. What it derives for the engine is in CompiledFrame, CompiledPoint and MassTerm.
struct FrameSpec {
  enum class Kind { kNewtonian, kAxisAngle, kDcm };
  std::string name;
  Kind kind = Kind::kNewtonian;
  int parent = -1;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // rotation axis, in the parent frame
  ScalarField angle;                                 // [rad]
  DcmFunction dcm;                                   // R_PF(q, t)
};

struct PointSpec {
  std::string name;
  int from = -1;                       // parent point
  int frame = 0;                       // frame the position vector is expressed in
  std::array<ScalarField, 3> position; // components [m]
};

// What Build() derives from a FrameSpec (Model::compiled_frames(), indexed like frames()).
struct CompiledFrame {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // kAxisAngle: the spec's axis, unit length
  // kAxisAngle: 0, 1 or 2 if `axis` is the parent's unit vector x, y or z (then R_NF is two
  // column rotations of R_NP, no 3 × 3 product), −1 otherwise.
  int axis_index = -1;
  // A constant angle: R_PF, and its cosine and sine, precomputed.
  bool constant_rotation = false;
  Eigen::Matrix3d constant_R_PF = Eigen::Matrix3d::Identity();
  double constant_cos = 1.0;
  double constant_sin = 0.0;
  // The angle is affine and q̇ = u: the engine evaluates it inline, writing its constant
  // partial rates straight into the columns.
  bool affine_angle = false;
  std::vector<int> active;  // speeds u_j whose partial angular velocity may be non-zero
  std::vector<int> fresh;   // active here but not in the parent (columns start from zero)
};

// What Build() derives from a PointSpec (Model::compiled_points(), indexed like points()).
struct CompiledPoint {
  // One term c·q_k of an affine position component: its partial rate ∂ṙ_c/∂u_k = c.
  struct RateTerm {
    int component;       // 0, 1, 2
    int speed;           // k
    double coefficient;  // c [m per unit of q_k]
  };
  std::vector<int> active;  // speeds whose partial velocity may be non-zero
  // Every component affine and q̇ = u: the relative position's partial rates are the
  // constant `rate_terms` (the engine's fast path, no scratch to clear), the constant parts
  // of the components are `offset` [m] and their time rates `time_rate` [m/s].
  bool affine = false;
  std::vector<RateTerm> rate_terms;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  Eigen::Vector3d time_rate = Eigen::Vector3d::Zero();
  bool has_time_rate = false;
  // The active speeds split by where their partial velocity starts: active for `from` only
  // (copy from's column), for `frame` only (ω_j × ρ), for both (the sum), or for neither
  // (zero; only the rate terms contribute).
  std::vector<int> from_only;
  std::vector<int> frame_only;
  std::vector<int> from_and_frame;
  std::vector<int> fresh;
};

struct ParticleSpec {
  std::string name;
  int point = -1;
  double mass = 0.0;  // [kg]
};

struct RigidBodySpec {
  std::string name;
  int frame = -1;            // body-fixed frame
  int mass_center = -1;      // point
  double mass = 0.0;         // [kg]
  Eigen::Matrix3d inertia;   // about the mass centre, in the body frame [kg·m²]
};

struct LoadSpec {
  enum class Kind { kForce, kTorque };
  std::string name;
  Kind kind = Kind::kForce;
  int target = -1;       // point (force) or frame (torque)
  int expressed_in = 0;  // frame the returned vector is expressed in
  LoadFunction function; // [N] or [N·m]
};

struct TimeFunctionSpec {
  std::string name;
  TimeFunction function;  // f(t), any unit
};

// An extra first-order state z_k: ż_k = rate(t, q, u, z) (LoadArgs with r empty), and its
// value at the start of a run.
struct ExtraStateSpec {
  QuantityInfo info;     // name "z_gen", unit "rad", description
  double initial = 0.0;  // z_k(0), in info.unit
  RateFunction rate;     // [info.unit / s]
};

struct SlotSpec {
  QuantityInfo info;         // name "r1", unit "N"
  ScalarField displacement;  // what the slot's substructure sees: d(q) [m] (or [rad])
};

// One term of the mass matrix from a point mass (a particle, or a rigid body's mass centre),
// derived by Build(): M_jk += mass v_j·v_k (and M_kj for j ≠ k), one for every pair j ≤ k of
// the point's active speeds, so CalcMassMatrix runs one flat loop. vj and vk are the offsets
// of v_j and v_k in the point's 3 × n column-major partial velocities, m_jk and m_kj those of
// M_jk and M_kj in the n × n column-major mass matrix.
struct MassTerm {
  int point = -1;
  int j = -1;
  int k = -1;
  double mass = 0.0;  // [kg]
  int vj = 0;
  int vk = 0;
  int m_jk = 0;
  int m_kj = 0;
  // In Model::grouped_mass_terms(): adds to the previous term's entry (else starts its sum).
  bool continues = false;
};

// One term of Kane's generalized forces: g_j += column j of a loaded point's partial velocity
// (frame: partial angular velocity) · its resultant force (torque). Model::projection_terms()
// holds them grouped by j, in the order points then frames within a j; `continues` as in
// MassTerm.
struct ProjectionTerm {
  bool frame = false;
  bool continues = false;
  int index = -1;  // point or frame
  int j = -1;
};

// The mass matrix of a tree of joints (composite-rigid-body form; decision 0012), derived by
// Build() when the model qualifies (Model::tree_mass_matrix()). Each speed u_j is then a joint
// with one spatial axis S_j = (ω_j, v_j(O)) in N shared by every mass element it moves: the
// rotation axis of the one frame whose angle holds q_j (a revolute joint about a pivot), or
// the translation of the one point whose position holds q_j (a prismatic joint). With the
// spatial momentum H_k = Σ_{elements moved by u_k} (m v_k, p × m v_k + I ω_k) about O,
//   M_jk = ω_j·H_k,ang + v_j(O)·H_k,lin      (u_j moves every element u_k moves),
// which costs O(Σ_elements |active|) = O(n·depth) instead of O(Σ_elements |active|²).
struct TreeMassPlan {
  struct Joint {
    int frame = -1;  // revolute: the frame whose angle holds q_j (ω_j is its column j); −1
    int pivot = -1;  // revolute: a point u_j does not move that sits on the axis, or −1
    int point = -1;  // prismatic: the point whose position holds q_j (v_j is its column j)
  };
  struct Element {  // a particle, or a rigid body's mass centre and frame
    int point = -1;
    int frame = -1;  // −1 for a particle
    double mass = 0.0;                                    // [kg]
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();    // about the mass centre, body axes
    bool has_inertia = false;
  };
  struct Pair {  // M_jk = M_kj = S_outer · H_inner
    int outer = -1;
    int inner = -1;
    int m_jk = 0;  // offsets in the n × n column-major M
    int m_kj = 0;
  };
  std::vector<Joint> joints;      // (n)
  std::vector<Element> elements;
  std::vector<Pair> pairs;        // every structurally non-zero M_jk, j ≤ k
  // The joint tree, for composite inertias: element e belongs to joint owner[e] (the
  // innermost speed that moves it, −1 if none); parent[k] is the next joint out (−1 at a
  // root); `order` lists the joints that move anything, children before parents.
  std::vector<int> owner;   // (elements)
  std::vector<int> parent;  // (n)
  std::vector<int> order;
};

// A sparse Cholesky factorisation of M (Model::sparse_factor()), derived by Build() for models
// whose factor is sparse enough to pay (a branched tree: the branches do not couple). M is
// factored as P M Pᵀ = L Lᵀ, P reversing the speeds when that gives less fill-in (a tree listed
// parents first then factors leaves first, with no fill-in: Featherstone's LTL). Row i of L
// has its non-zeros left of the diagonal at columns `columns[row_start[i] .. row_start[i+1])`,
// ascending.
struct SparseFactorPlan {
  bool reversed = false;
  std::vector<int> row_start;  // (n + 1)
  std::vector<int> columns;
};

// Everything a model is made of, as the builder collects it and the built model holds it
// (Build() moves it across).
struct ModelElements {
  std::vector<QuantityInfo> coordinates;
  std::vector<QuantityInfo> speeds;
  std::vector<FrameSpec> frames;
  std::vector<PointSpec> points;
  std::vector<ParticleSpec> particles;
  std::vector<RigidBodySpec> bodies;
  std::vector<LoadSpec> loads;
  std::vector<SlotSpec> slots;
  std::vector<TimeFunctionSpec> time_functions;
  KinematicMatrixFunction kinematic_matrix;  // empty: q̇ = u
  std::vector<ExtraStateSpec> extra_states;
  std::vector<ConstraintSpec> constraints;  // closed loops, rolling (constraint_spec.h)
  ConstraintOptions constraint_options;
  std::vector<double> initial_q, initial_u;  // ModelBuilder::SetInitialState (empty: zero)
};

// One row of the velocity constraints B u + c = 0 (Model::constraint_rows()).
struct ConstraintRow {
  int constraint = -1;  // index in Model::constraints()
  int component = 0;    // kCoincident, kVelocity: 0, 1, 2; otherwise 0
  bool holonomic = false;
};

class Model;

namespace internal {
// A number that no other Model object holds: drawn anew by every construction, copy and
// assignment (a move too), so that what a workspace precomputed for one model (data.h,
// EvaluationPlan) is never taken for another's, even one built at the same address or
// assigned into the same object.
class ModelInstanceId {
 public:
  ModelInstanceId() : value_(Next()) {}
  ModelInstanceId(const ModelInstanceId&) : value_(Next()) {}
  ModelInstanceId& operator=(const ModelInstanceId&) {
    value_ = Next();
    return *this;
  }
  std::uint64_t value() const { return value_; }

 private:
  static std::uint64_t Next();
  std::uint64_t value_;
};
}  // namespace internal

class ModelBuilder {
 public:
  // n generalized coordinates; speeds are named u1..un after them unless given.
  explicit ModelBuilder(std::vector<QuantityInfo> coordinates,
                        std::vector<QuantityInfo> speeds = {});

  FrameId newtonian() const { return FrameId{0}; }
  PointId origin() const { return PointId{0}; }

  // Frame rotated from `parent` about the fixed unit `axis` (parent components) by `angle`.
  FrameId AddFrameAboutAxis(std::string name, FrameId parent, const Eigen::Vector3d& axis,
                            ScalarField angle);
  // Frame with a general direction-cosine matrix R_PF(q, t) (must be a rotation).
  FrameId AddFrameWithDcm(std::string name, FrameId parent, DcmFunction dcm);
  // Point located from `from` by a vector with components `position` in `expressed_in`.
  PointId AddPoint(std::string name, PointId from, FrameId expressed_in,
                   std::array<ScalarField, 3> position);
  void AddParticle(std::string name, PointId point, double mass);
  // Rigid body fixed in `frame` with mass centre `mass_center`; inertia about the mass centre
  // in `frame` components (symmetric, positive semi-definite) [kg·m²].
  void AddRigidBody(std::string name, FrameId frame, PointId mass_center, double mass,
                    const Eigen::Matrix3d& inertia);
  // A force [N] acting at `point`, returned by f in `expressed_in` components.
  template <class F>
  void AddForce(std::string name, PointId point, FrameId expressed_in, const F& f) {
    AddLoad(std::move(name), LoadSpec::Kind::kForce, point.index, expressed_in,
            LoadFunction(f));
  }
  // A torque [N·m] acting on `frame`, returned by f in `expressed_in` components.
  template <class F>
  void AddTorque(std::string name, FrameId frame, FrameId expressed_in, const F& f) {
    AddLoad(std::move(name), LoadSpec::Kind::kTorque, frame.index, expressed_in,
            LoadFunction(f));
  }
  // Declares a function of time alone, f(t) (a generic lambda `[](const auto& t) { ... }`
  // returning the same scalar type), e.g. a load ramp ρ(t) = 1 − e^{−t/t0}. It is evaluated
  // once per CalcForcing and every load reads it as `a.time_function(k)`, with k the index
  // returned here, so an expensive ramp shared by many loads costs one evaluation.
  template <class F>
  int AddTimeFunction(std::string name, const F& f) {
    return AddTimeFunctionSpec(std::move(name), TimeFunction(f));
  }
  // Declares a restoring-force slot r^s; returns its index in r. `unit` is "N" (a force; the
  // displacement is in m) or "N·m" (a moment; the displacement is in rad).
  int AddRestoringForceSlot(std::string name, std::string description,
                            ScalarField displacement, std::string unit = "N");
  // Declares an extra first-order state z_k with ż_k = rate(a) (a generic lambda of LoadArgs
  // returning the scalar; a.r is empty) and z_k(0) = initial; returns k. Loads read it as
  // a.z[k]. It joins the state after q and u: x = [q; u; z].
  template <class F>
  int AddExtraState(QuantityInfo info, double initial, const F& rate) {
    elements_.extra_states.push_back({std::move(info), initial, RateFunction(rate)});
    return static_cast<int>(elements_.extra_states.size()) - 1;
  }
  // q̇ = W(q) u with W filled by f (see KinematicMatrixSignature).
  template <class F>
  void SetKinematicalEquations(const F& f) {
    elements_.kinematic_matrix = KinematicMatrixFunction(f);
  }

  // Constraints (constraint_spec.h, equations in constraints.h). A configuration constraint
  // f(q, t) = 0 [m, rad or 1]:
  void AddHolonomicConstraint(std::string name, ScalarField f);
  // A velocity constraint Σ_j B_j(q, t) u_j + c(q, t) = 0, linear in u by construction.
  void AddNonholonomicConstraint(std::string name,
                                 std::vector<std::pair<int, ScalarField>> coefficients,
                                 ScalarField constant);
  // Points P and Q coincide: the `components` (0, 1, 2) of p_OP − p_OQ in `expressed_in`
  // vanish (a closed loop).
  void AddCoincidenceConstraint(std::string name, PointId P, PointId Q, FrameId expressed_in,
                                std::vector<int> components);
  // The velocity of P in N has zero `components` in `expressed_in`. With `body` given, P is
  // taken as the point of `body` that coincides with it, v = v_C + ω_body × (p_P − p_C) with C
  // = `body_point` fixed in `body`: a wheel rolling without slip at its contact point P.
  void AddVelocityConstraint(std::string name, PointId P, FrameId expressed_in,
                             std::vector<int> components, FrameId body = FrameId{-1},
                             PointId body_point = PointId{-1});
  void SetConstraintOptions(ConstraintOptions options);
  // Record the force of the constraint `name` (its multipliers λ, unit `force_unit`) as journal
  // channels (ConstraintSpec::record_force). Throws ModelError if no constraint has that name.
  void RecordConstraintForce(const std::string& name, std::string force_unit);
  // The state a run starts from unless its config says otherwise, and the operating point of
  // a linearisation: q (n) [SI], u (n) [SI]; default zero.
  void SetInitialState(std::vector<double> q, std::vector<double> u);

  // Validates (ids, masses, inertia, a positive-definite mass matrix is the user's job) and
  // freezes the model. Throws ModelError naming the element at fault.
  Model Build() &&;

 private:
  friend class Model;
  void AddLoad(std::string name, LoadSpec::Kind kind, int target, FrameId expressed_in,
               LoadFunction f);
  int AddTimeFunctionSpec(std::string name, TimeFunction f);
  void CheckFrame(FrameId f, const std::string& what) const;
  void CheckPoint(PointId p, const std::string& what) const;
  void CheckField(const ScalarField& field, const std::string& what) const;

  ModelElements elements_;
};

class Model {
 public:
  int num_coordinates() const { return static_cast<int>(elements_.coordinates.size()); }
  int num_speeds() const { return num_coordinates(); }
  int num_extra_states() const { return static_cast<int>(elements_.extra_states.size()); }
  // x = [q; u; z]: 2n + nz.
  int num_states() const { return 2 * num_coordinates() + num_extra_states(); }
  const std::vector<ExtraStateSpec>& extra_states() const { return elements_.extra_states; }
  int num_slots() const { return static_cast<int>(elements_.slots.size()); }
  const std::vector<QuantityInfo>& coordinates() const { return elements_.coordinates; }
  const std::vector<QuantityInfo>& speeds() const { return elements_.speeds; }
  const std::vector<FrameSpec>& frames() const { return elements_.frames; }
  const std::vector<PointSpec>& points() const { return elements_.points; }
  const std::vector<ParticleSpec>& particles() const { return elements_.particles; }
  const std::vector<RigidBodySpec>& bodies() const { return elements_.bodies; }
  const std::vector<LoadSpec>& loads() const { return elements_.loads; }
  const std::vector<SlotSpec>& slots() const { return elements_.slots; }
  const std::vector<TimeFunctionSpec>& time_functions() const { return elements_.time_functions; }
  // Constraints: m = num_constraint_rows() velocity constraints B u + c = 0 (constraints.h).
  bool has_constraints() const { return !constraint_rows_.empty(); }
  const std::vector<ConstraintSpec>& constraints() const { return elements_.constraints; }
  const ConstraintOptions& constraint_options() const { return elements_.constraint_options; }
  const std::vector<ConstraintRow>& constraint_rows() const { return constraint_rows_; }
  int num_constraint_rows() const { return static_cast<int>(constraint_rows_.size()); }
  int num_holonomic_rows() const { return num_holonomic_rows_; }
  // x0 = [q0; u0; z0] (2n + nz): SetInitialState's q and u (zero if not set) and the extra
  // states' initial values. Not assembled: see AssembleState (assembly.h).
  Eigen::VectorXd initial_state() const;
  // What Build() derived from frames() and points() for the engine, indexed like them.
  const std::vector<CompiledFrame>& compiled_frames() const { return compiled_frames_; }
  const std::vector<CompiledPoint>& compiled_points() const { return compiled_points_; }
  bool has_identity_kinematics() const { return !elements_.kinematic_matrix; }
  const KinematicMatrixFunction& kinematic_matrix() const { return elements_.kinematic_matrix; }
  // Translational mass-matrix terms of all particles and rigid-body mass centres.
  const std::vector<MassTerm>& mass_terms() const { return mass_terms_; }
  // n ≤ kGroupedSumsMax: doubles sum each entry of M and of g in a register, from
  // grouped_mass_terms() (mass_terms() grouped by entry, their order kept within an entry,
  // the constant entries left out) and projection_terms(), instead of adding term by term
  // into memory.
  static constexpr int kGroupedSumsMax = 8;
  bool grouped_sums() const { return grouped_sums_; }
  const std::vector<MassTerm>& grouped_mass_terms() const { return grouped_mass_terms_; }
  // Points and frames that receive a force/torque or carry mass (visited by CalcForcing).
  const std::vector<int>& loaded_points() const { return loaded_points_; }
  const std::vector<int>& loaded_frames() const { return loaded_frames_; }
  const std::vector<ProjectionTerm>& projection_terms() const { return projection_terms_; }
  // Indices of loads acting on each point/frame, for accumulation.
  bool has_general_fields() const { return has_general_fields_; }
  // 0, 1 or 2 if every frame turns about that axis of N (by an affine or constant angle) and
  // every point is affine, with q̇ = u: the kinematics then skip the structural zeros of R, ω
  // and α for doubles (decision 0012); −1 otherwise.
  int planar_axis() const { return planar_axis_; }
  // True if the model is a tree of joints with q̇ = u (TreeMassPlan, then non-empty).
  bool is_joint_tree() const { return is_joint_tree_; }
  // True if CalcMassMatrix takes the O(n·depth) composite path: a joint tree on which it
  // costs less than the pairwise path (mass_terms()); small models such as the paper's rotor
  // keep the pairwise sum, which is cheaper there (decision 0012).
  bool tree_mass_matrix() const { return tree_mass_matrix_; }
  const TreeMassPlan& tree_mass_plan() const { return tree_mass_plan_; }
  // Why the model takes the pairwise path (empty if it takes the tree path).
  const std::string& tree_mass_matrix_reason() const { return tree_mass_matrix_reason_; }
  // Structure of the Cholesky factor L of M = L Lᵀ, fill-in included: n × n column-major,
  // 1 where L_ij (i ≥ j) may be non-zero. The solve skips the structural zeros (exactly).
  const std::vector<char>& factor_pattern() const { return factor_pattern_; }
  // True if the solve takes the sparse factorisation (sparse_factor_plan()).
  bool sparse_factor() const { return !sparse_factor_plan_.row_start.empty(); }
  // The constant entries of M and columns of its factor (planar models on the pairwise path
  // with n ≤ 6; otherwise `entry` is empty). See constant_mass.h.
  const ConstantMassPlan& constant_mass() const { return constant_mass_; }
  const SparseFactorPlan& sparse_factor_plan() const { return sparse_factor_plan_; }
  // The model's right-hand side compiled to machine code, or null (symbolic_compiled.h):
  // CalcStateDerivative<double> then calls it in place of the kinematics, M and g. Attach only
  // one that symbolic::LoadCompiledModel has checked against this model; null detaches.
  const CompiledRhs* compiled_rhs() const { return compiled_rhs_.get(); }
  void AttachCompiledRhs(std::shared_ptr<const CompiledRhs> rhs) { compiled_rhs_ = std::move(rhs); }
  // This object's content, as a number no other Model object holds (internal::ModelInstanceId).
  std::uint64_t instance_id() const { return instance_id_.value(); }

 private:
  friend class ModelBuilder;
  Model() = default;
  ModelElements elements_;
  std::vector<ConstraintRow> constraint_rows_;
  int num_holonomic_rows_ = 0;
  std::vector<CompiledFrame> compiled_frames_;
  std::vector<CompiledPoint> compiled_points_;
  std::vector<MassTerm> mass_terms_;
  std::vector<MassTerm> grouped_mass_terms_;
  std::vector<int> loaded_points_;
  std::vector<int> loaded_frames_;
  std::vector<ProjectionTerm> projection_terms_;
  bool grouped_sums_ = false;
  bool has_general_fields_ = false;
  int planar_axis_ = -1;
  bool is_joint_tree_ = false;
  bool tree_mass_matrix_ = false;
  TreeMassPlan tree_mass_plan_;
  std::string tree_mass_matrix_reason_;
  std::shared_ptr<const CompiledRhs> compiled_rhs_;
  std::vector<char> factor_pattern_;
  SparseFactorPlan sparse_factor_plan_;
  ConstantMassPlan constant_mass_;
  internal::ModelInstanceId instance_id_;
};

}  // namespace hybridtest::multibody
