// Model construction and validation. See model.h.
#include "hybridtest/multibody/model.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/compile.h"
#include "hybridtest/multibody/tree_mass.h"

namespace hybridtest::multibody {

std::uint64_t internal::ModelInstanceId::Next() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

ScalarField ScalarField::Constant(double value) {
  ScalarField f;
  f.constant_ = value;
  return f;
}

ScalarField ScalarField::Coordinate(int k, double scale, double offset) {
  return Affine(offset, {{k, scale}});
}

ScalarField ScalarField::Affine(double constant, std::vector<Term> terms, double time_rate) {
  ScalarField f;
  f.constant_ = constant;
  for (const Term& t : terms) {
    if (t.coefficient != 0.0) f.terms_.push_back(t);
  }
  f.time_rate_ = time_rate;
  return f;
}

int ScalarField::max_coordinate() const {
  int m = -1;
  for (const Term& t : terms_) m = std::max(m, t.coordinate);
  return m;
}

namespace internal {
// The rows of B u + c = 0 from the constraints, with the options checked (constraint_builder.cc).
void CompileConstraintRows(const ModelElements& e, std::vector<ConstraintRow>& rows,
                           int& num_holonomic);
}  // namespace internal

namespace {
// Evaluates every DCM frame at q = 0 and at two pseudo-random q (t = 0) and refuses one that
// is not a rotation (RᵀR = I, det R = +1, to 1e-9): a wrong DCM would silently give wrong
// equations of motion.
void CheckDcmFrames(const ModelElements& e) {
  const int n = static_cast<int>(e.coordinates.size());
  std::vector<Jet<double>> q(static_cast<std::size_t>(n));
  std::array<Jet<double>, 9> c;
  for (int trial = 0; trial < 3; ++trial) {
    for (int k = 0; k < n; ++k) q[k] = Jet<double>(trial == 0 ? 0.0 : std::sin(1.3 * k + 0.7 * trial));
    const KinematicArgs<double> args{std::span<const Jet<double>>(q.data(), q.size()), Jet<double>(0.0)};
    for (const FrameSpec& f : e.frames) {
      if (f.kind != FrameSpec::Kind::kDcm) continue;
      f.dcm.get<double>()(args, std::span<Jet<double>>(c.data(), 9));
      Eigen::Matrix3d R;
      for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = c[i].v;
      const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
      if (!(orth < 1e-9) || !(R.determinant() > 0.0)) {
        throw ModelError(fmt::format("frame '{}': its direction-cosine matrix is not a rotation "
                                     "at q = [{}] (|RᵀR − I| = {:.3g}, det R = {:.6g}); it must "
                                     "be orthonormal with determinant +1 for every q",
                                     f.name, trial == 0 ? "0, ..." : "random", orth,
                                     R.determinant()));
      }
    }
  }
}
}  // namespace

ModelBuilder::ModelBuilder(std::vector<QuantityInfo> coordinates,
                           std::vector<QuantityInfo> speeds) {
  elements_.coordinates = std::move(coordinates);
  elements_.speeds = std::move(speeds);
  const int n = static_cast<int>(elements_.coordinates.size());
  if (n < 1) throw ModelError("a model needs at least one generalized coordinate; got none");
  if (elements_.speeds.empty()) {
    for (int k = 0; k < n; ++k) {
      const std::string unit = elements_.coordinates[k].unit + "/s";
      elements_.speeds.push_back({fmt::format("u{}", k + 1), unit,
                         "time derivative of " + elements_.coordinates[k].name});
    }
  }
  if (static_cast<int>(elements_.speeds.size()) != n) {
    throw ModelError(fmt::format("a model needs as many generalized speeds as coordinates: {} "
                                 "coordinates but {} speeds", n, elements_.speeds.size()));
  }
  FrameSpec newtonian;
  newtonian.name = "N";
  elements_.frames.push_back(newtonian);
  PointSpec origin;
  origin.name = "O";
  elements_.points.push_back(origin);
}

void ModelBuilder::CheckFrame(FrameId f, const std::string& what) const {
  if (f.index < 0 || f.index >= static_cast<int>(elements_.frames.size())) {
    throw ModelError(fmt::format("{}: frame id {} does not exist (the model has {} frames); "
                                 "use an id returned by AddFrame*", what, f.index,
                                 elements_.frames.size()));
  }
}

void ModelBuilder::CheckPoint(PointId p, const std::string& what) const {
  if (p.index < 0 || p.index >= static_cast<int>(elements_.points.size())) {
    throw ModelError(fmt::format("{}: point id {} does not exist (the model has {} points); "
                                 "use an id returned by AddPoint", what, p.index,
                                 elements_.points.size()));
  }
}

void ModelBuilder::CheckField(const ScalarField& field, const std::string& what) const {
  const int n = static_cast<int>(elements_.coordinates.size());
  if (field.is_affine()) {
    if (field.max_coordinate() >= n) {
      throw ModelError(fmt::format("{}: refers to coordinate index {} but the model has {} "
                                   "coordinates (indices are 0-based)", what,
                                   field.max_coordinate(), n));
    }
    for (const auto& t : field.terms()) {
      if (t.coordinate < 0) throw ModelError(what + ": negative coordinate index");
      if (!std::isfinite(t.coefficient)) throw ModelError(what + ": non-finite coefficient");
    }
    if (!std::isfinite(field.constant()) || !std::isfinite(field.time_rate())) {
      throw ModelError(what + ": non-finite constant or time rate");
    }
  }
}

FrameId ModelBuilder::AddFrameAboutAxis(std::string name, FrameId parent,
                                        const Eigen::Vector3d& axis, ScalarField angle) {
  const std::string what = "frame '" + name + "'";
  CheckFrame(parent, what);
  CheckField(angle, what + " angle");
  const double norm = axis.norm();
  if (!(norm > 1e-12) || !axis.allFinite()) {
    throw ModelError(what + ": the rotation axis must be a finite non-zero vector");
  }
  FrameSpec f;
  f.name = std::move(name);
  f.kind = FrameSpec::Kind::kAxisAngle;
  f.parent = parent.index;
  f.axis = axis;
  f.angle = std::move(angle);
  elements_.frames.push_back(std::move(f));
  return FrameId{static_cast<int>(elements_.frames.size()) - 1};
}

FrameId ModelBuilder::AddFrameWithDcm(std::string name, FrameId parent, DcmFunction dcm) {
  const std::string what = "frame '" + name + "'";
  CheckFrame(parent, what);
  if (!dcm) throw ModelError(what + ": the direction-cosine function is empty");
  FrameSpec f;
  f.name = std::move(name);
  f.kind = FrameSpec::Kind::kDcm;
  f.parent = parent.index;
  f.dcm = std::move(dcm);
  elements_.frames.push_back(std::move(f));
  return FrameId{static_cast<int>(elements_.frames.size()) - 1};
}

PointId ModelBuilder::AddPoint(std::string name, PointId from, FrameId expressed_in,
                               std::array<ScalarField, 3> position) {
  const std::string what = "point '" + name + "'";
  CheckPoint(from, what);
  CheckFrame(expressed_in, what);
  for (int c = 0; c < 3; ++c) CheckField(position[c], fmt::format("{} component {}", what, c));
  PointSpec p;
  p.name = std::move(name);
  p.from = from.index;
  p.frame = expressed_in.index;
  p.position = std::move(position);
  elements_.points.push_back(std::move(p));
  return PointId{static_cast<int>(elements_.points.size()) - 1};
}

void ModelBuilder::AddParticle(std::string name, PointId point, double mass) {
  const std::string what = "particle '" + name + "'";
  CheckPoint(point, what);
  if (!(mass > 0.0) || !std::isfinite(mass)) {
    throw ModelError(fmt::format("{}: mass = {}: expected a positive mass in kg", what, mass));
  }
  elements_.particles.push_back({std::move(name), point.index, mass});
}

void ModelBuilder::AddRigidBody(std::string name, FrameId frame, PointId mass_center, double mass,
                                const Eigen::Matrix3d& inertia) {
  const std::string what = "rigid body '" + name + "'";
  CheckFrame(frame, what);
  CheckPoint(mass_center, what);
  if (!(mass >= 0.0) || !std::isfinite(mass)) {
    throw ModelError(fmt::format("{}: mass = {}: expected a non-negative mass in kg", what, mass));
  }
  if (!inertia.allFinite() || (inertia - inertia.transpose()).cwiseAbs().maxCoeff() >
                                  1e-12 * std::max(1.0, inertia.cwiseAbs().maxCoeff())) {
    throw ModelError(what + ": the inertia matrix must be finite and symmetric [kg·m²]");
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  if (eig.eigenvalues().minCoeff() < -1e-12 * std::max(1.0, inertia.norm())) {
    throw ModelError(fmt::format("{}: the inertia matrix has a negative principal moment ({}); "
                                 "expected positive semi-definite", what,
                                 eig.eigenvalues().minCoeff()));
  }
  elements_.bodies.push_back({std::move(name), frame.index, mass_center.index, mass, inertia});
}

void ModelBuilder::AddLoad(std::string name, LoadSpec::Kind kind, int target, FrameId expressed_in,
                           LoadFunction f) {
  const std::string what = "load '" + name + "'";
  if (kind == LoadSpec::Kind::kForce) {
    CheckPoint(PointId{target}, what);
  } else {
    CheckFrame(FrameId{target}, what);
  }
  CheckFrame(expressed_in, what);
  if (!f) throw ModelError(what + ": the load function is empty");
  elements_.loads.push_back({std::move(name), kind, target, expressed_in.index, std::move(f)});
}

int ModelBuilder::AddTimeFunctionSpec(std::string name, TimeFunction f) {
  if (!f) throw ModelError("time function '" + name + "': the function is empty");
  for (const auto& tf : elements_.time_functions) {
    if (tf.name == name) throw ModelError("time function '" + name + "' declared twice");
  }
  elements_.time_functions.push_back({std::move(name), std::move(f)});
  return static_cast<int>(elements_.time_functions.size()) - 1;
}

int ModelBuilder::AddRestoringForceSlot(std::string name, std::string description,
                                        ScalarField displacement, std::string unit) {
  CheckField(displacement, "restoring-force slot '" + name + "'");
  if (unit != "N" && unit != "N·m") {
    throw ModelError(fmt::format("restoring-force slot '{}': unit '{}': expected N (a force) or "
                                 "N·m (a moment)", name, unit));
  }
  for (const auto& s : elements_.slots) {
    if (s.info.name == name) throw ModelError("restoring-force slot '" + name + "' declared twice");
  }
  elements_.slots.push_back(
      {{std::move(name), std::move(unit), std::move(description)}, std::move(displacement)});
  return static_cast<int>(elements_.slots.size()) - 1;
}

Model ModelBuilder::Build() && {
  if (elements_.particles.empty() && elements_.bodies.empty()) {
    throw ModelError("the model has no mass: add at least one particle or rigid body");
  }
  internal::CompiledKinematics compiled = internal::CompileKinematics(elements_);
  // A non-affine constraint expression is evaluated on jets, as a general field is.
  bool constraints_general = false;
  for (const ConstraintSpec& c : elements_.constraints) {
    constraints_general = constraints_general || !c.field.is_affine() || !c.constant.is_affine();
    for (const auto& [j, field] : c.coefficients) {
      constraints_general = constraints_general || !field.is_affine();
    }
  }
  const bool general = compiled.general || constraints_general;
  // Jets (general expressions, W(q), DCM frames) carry ∂/∂q inline for up to
  // kMaxJetCoordinates coordinates; affine models have no such cap.
  const int num_q = static_cast<int>(elements_.coordinates.size());
  if (general && num_q > kMaxJetCoordinates) {
    throw ModelError(fmt::format("a model with general (non-affine) kinematic expressions, "
                                 "kinematical equations W(q) or DCM frames may have at most {} "
                                 "generalized coordinates; got {} (affine models have no cap)",
                                 kMaxJetCoordinates, num_q));
  }
  if (general) CheckDcmFrames(elements_);
  Model m;
  std::set<int> loaded_points, loaded_frames;
  for (const auto& pa : elements_.particles) loaded_points.insert(pa.point);
  for (const auto& b : elements_.bodies) {
    loaded_points.insert(b.mass_center);
    loaded_frames.insert(b.frame);
  }
  for (const auto& l : elements_.loads) {
    (l.kind == LoadSpec::Kind::kForce ? loaded_points : loaded_frames).insert(l.target);
  }
  const int n = static_cast<int>(elements_.coordinates.size());
  m.mass_terms_ = internal::CompileMassTerms(elements_, compiled.points);
  m.loaded_points_.assign(loaded_points.begin(), loaded_points.end());
  m.loaded_frames_.assign(loaded_frames.begin(), loaded_frames.end());
  m.has_general_fields_ = general;
  m.planar_axis_ = compiled.planar_axis;
  m.tree_mass_matrix_reason_ = internal::PlanTreeMassMatrix(elements_, compiled.frames,
                                                            compiled.points, m.tree_mass_plan_);
  m.is_joint_tree_ = m.tree_mass_matrix_reason_.empty();
  if (!m.is_joint_tree_) {
    m.tree_mass_plan_ = TreeMassPlan{};
  } else {
    // Estimated cost in flops (calibrated with bench/bench_kane_scale.cc): the pairwise sum
    // ~6 per mass term and ~8 per rotational pair; the tree path ~60 per joint (axis,
    // composite, momentum), ~45 per element and ~7 per pair.
    std::size_t pairwise = 6 * m.mass_terms_.size();
    for (const auto& b : elements_.bodies) {
      const std::size_t a = compiled.frames[b.frame].active.size();
      pairwise += 8 * a * (a + 1) / 2 + 30;
    }
    const std::size_t tree = 60 * static_cast<std::size_t>(n) +
                             45 * m.tree_mass_plan_.elements.size() +
                             7 * m.tree_mass_plan_.pairs.size();
    m.tree_mass_matrix_ = tree < pairwise;
    if (!m.tree_mass_matrix_) {
      m.tree_mass_matrix_reason_ = fmt::format(
          "a tree of joints, but the pairwise sum is cheaper here (~{} against ~{} flops)",
          pairwise, tree);
    }
  }
  const std::vector<char> structure =
      internal::CompileMassStructure(elements_, compiled.frames, m.mass_terms_, m.tree_mass_plan_);
  m.factor_pattern_ = internal::CompileFactorPattern(structure, n);
  m.sparse_factor_plan_ = internal::CompileSparseFactor(structure, n);
  if (!m.tree_mass_matrix_ && !m.sparse_factor()) {
    m.constant_mass_ = internal::CompileConstantMass(elements_, compiled.frames, compiled.points,
                                                     m.planar_axis_, m.factor_pattern_);
    if (!m.constant_mass_.any()) m.constant_mass_ = ConstantMassPlan{};
  }
  // Small models sum M's entries and the generalized forces entry by entry in a register
  // (Model::grouped_sums()); larger ones keep the point-by-point loops, whose memory access
  // is sequential. The constant entries' terms are not evaluated.
  m.grouped_sums_ = n <= Model::kGroupedSumsMax;
  if (m.grouped_sums_) {
    for (const MassTerm& t : m.mass_terms_) {
      const auto& constant = m.constant_mass_.entry;
      if (constant.empty() || !constant[static_cast<std::size_t>(t.m_jk)]) {
        m.grouped_mass_terms_.push_back(t);
      }
    }
    std::stable_sort(m.grouped_mass_terms_.begin(), m.grouped_mass_terms_.end(),
                     [](const MassTerm& a, const MassTerm& b) { return a.m_jk < b.m_jk; });
    for (std::size_t t = 1; t < m.grouped_mass_terms_.size(); ++t) {
      m.grouped_mass_terms_[t].continues =
          m.grouped_mass_terms_[t].m_jk == m.grouped_mass_terms_[t - 1].m_jk;
    }
    for (int p : m.loaded_points_)
      for (int j : compiled.points[p].active) m.projection_terms_.push_back({false, false, p, j});
    for (int f : m.loaded_frames_)
      for (int j : compiled.frames[f].active) m.projection_terms_.push_back({true, false, f, j});
    std::stable_sort(m.projection_terms_.begin(), m.projection_terms_.end(),
                     [](const ProjectionTerm& a, const ProjectionTerm& b) { return a.j < b.j; });
    for (std::size_t t = 1; t < m.projection_terms_.size(); ++t)
      m.projection_terms_[t].continues = m.projection_terms_[t].j == m.projection_terms_[t - 1].j;
  }
  internal::CompileConstraintRows(elements_, m.constraint_rows_, m.num_holonomic_rows_);
  m.compiled_frames_ = std::move(compiled.frames);
  m.compiled_points_ = std::move(compiled.points);
  m.elements_ = std::move(elements_);
  return m;
}

}  // namespace hybridtest::multibody
