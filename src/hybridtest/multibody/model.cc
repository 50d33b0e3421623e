// Model construction and validation. See model.h.
#include "hybridtest/multibody/model.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "hybridtest/common/error.h"

namespace hybridtest::multibody {

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

namespace {
std::vector<int> Union(const std::vector<int>& a, const std::vector<int>& b) {
  std::set<int> s(a.begin(), a.end());
  s.insert(b.begin(), b.end());
  return {s.begin(), s.end()};
}
}  // namespace

ModelBuilder::ModelBuilder(std::vector<QuantityInfo> coordinates, std::vector<QuantityInfo> speeds)
    : coordinates_(std::move(coordinates)), speeds_(std::move(speeds)) {
  const int n = static_cast<int>(coordinates_.size());
  if (n < 1) throw ModelError("a model needs at least one generalized coordinate; got none");
  if (n > kMaxJetCoordinates) {
    throw ModelError(fmt::format("a model may have at most {} generalized coordinates; got {}",
                                 kMaxJetCoordinates, n));
  }
  if (speeds_.empty()) {
    for (int k = 0; k < n; ++k) {
      const std::string unit = coordinates_[k].unit + "/s";
      speeds_.push_back({fmt::format("u{}", k + 1), unit,
                         "time derivative of " + coordinates_[k].name});
    }
  }
  if (static_cast<int>(speeds_.size()) != n) {
    throw ModelError(fmt::format("a model needs as many generalized speeds as coordinates: {} "
                                 "coordinates but {} speeds", n, speeds_.size()));
  }
  FrameSpec newtonian;
  newtonian.name = "N";
  frames_.push_back(newtonian);
  PointSpec origin;
  origin.name = "O";
  points_.push_back(origin);
}

void ModelBuilder::CheckFrame(FrameId f, const std::string& what) const {
  if (f.index < 0 || f.index >= static_cast<int>(frames_.size())) {
    throw ModelError(fmt::format("{}: frame id {} does not exist (the model has {} frames); "
                                 "use an id returned by AddFrame*", what, f.index, frames_.size()));
  }
}

void ModelBuilder::CheckPoint(PointId p, const std::string& what) const {
  if (p.index < 0 || p.index >= static_cast<int>(points_.size())) {
    throw ModelError(fmt::format("{}: point id {} does not exist (the model has {} points); "
                                 "use an id returned by AddPoint", what, p.index, points_.size()));
  }
}

void ModelBuilder::CheckField(const ScalarField& field, const std::string& what) const {
  const int n = static_cast<int>(coordinates_.size());
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

// Speeds whose partial rate of `field` may be non-zero.
std::vector<int> ModelBuilder::FieldActive(const ScalarField& field) const {
  const int n = static_cast<int>(coordinates_.size());
  std::vector<int> all(n);
  for (int j = 0; j < n; ++j) all[j] = j;
  if (!field.is_affine() || kinematic_matrix_) return field.is_constant() ? std::vector<int>{} : all;
  std::vector<int> active;
  for (const auto& t : field.terms()) active.push_back(t.coordinate);
  return Union(active, {});
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
  f.axis = axis / norm;
  f.angle = std::move(angle);
  frames_.push_back(std::move(f));
  return FrameId{static_cast<int>(frames_.size()) - 1};
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
  frames_.push_back(std::move(f));
  return FrameId{static_cast<int>(frames_.size()) - 1};
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
  points_.push_back(std::move(p));
  return PointId{static_cast<int>(points_.size()) - 1};
}

void ModelBuilder::AddParticle(std::string name, PointId point, double mass) {
  const std::string what = "particle '" + name + "'";
  CheckPoint(point, what);
  if (!(mass > 0.0) || !std::isfinite(mass)) {
    throw ModelError(fmt::format("{}: mass = {}: expected a positive mass in kg", what, mass));
  }
  particles_.push_back({std::move(name), point.index, mass});
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
  bodies_.push_back({std::move(name), frame.index, mass_center.index, mass, inertia});
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
  loads_.push_back({std::move(name), kind, target, expressed_in.index, std::move(f)});
}

int ModelBuilder::AddTimeFunctionSpec(std::string name, TimeFunction f) {
  if (!f) throw ModelError("time function '" + name + "': the function is empty");
  for (const auto& tf : time_functions_) {
    if (tf.name == name) throw ModelError("time function '" + name + "' declared twice");
  }
  time_functions_.push_back({std::move(name), std::move(f)});
  return static_cast<int>(time_functions_.size()) - 1;
}

int ModelBuilder::AddRestoringForceSlot(std::string name, std::string description,
                                        ScalarField displacement) {
  CheckField(displacement, "restoring-force slot '" + name + "'");
  for (const auto& s : slots_) {
    if (s.info.name == name) throw ModelError("restoring-force slot '" + name + "' declared twice");
  }
  slots_.push_back({{std::move(name), "N", std::move(description)}, std::move(displacement)});
  return static_cast<int>(slots_.size()) - 1;
}

Model ModelBuilder::Build() && {
  if (particles_.empty() && bodies_.empty()) {
    throw ModelError("the model has no mass: add at least one particle or rigid body");
  }
  auto is_general = [](const ScalarField& f) { return !f.is_affine(); };
  bool general = static_cast<bool>(kinematic_matrix_);
  // Active speeds, frames first (parents precede children by construction).
  for (std::size_t i = 1; i < frames_.size(); ++i) {
    FrameSpec& f = frames_[i];
    std::vector<int> own;
    if (f.kind == FrameSpec::Kind::kAxisAngle) {
      own = FieldActive(f.angle);
      general = general || is_general(f.angle);
      if (f.angle.is_constant()) {
        f.constant_rotation = true;
        f.constant_R_PF = Eigen::AngleAxisd(f.angle.constant(), f.axis).toRotationMatrix();
      }
    } else {
      general = true;
      for (int j = 0; j < static_cast<int>(coordinates_.size()); ++j) own.push_back(j);
    }
    f.active = Union(frames_[f.parent].active, own);
  }
  for (std::size_t i = 1; i < points_.size(); ++i) {
    PointSpec& p = points_[i];
    std::vector<int> active = Union(points_[p.from].active, frames_[p.frame].active);
    for (const auto& c : p.position) {
      active = Union(active, FieldActive(c));
      general = general || is_general(c);
    }
    p.active = std::move(active);
    p.affine = !kinematic_matrix_ && std::all_of(p.position.begin(), p.position.end(),
                                                 [](const ScalarField& c) { return c.is_affine(); });
    if (p.affine) {
      for (int c = 0; c < 3; ++c)
        for (const auto& term : p.position[c].terms())
          p.rate_terms.push_back({c, term.coordinate, term.coefficient});
    }
  }
  Model m;
  std::set<int> loaded_points, loaded_frames;
  for (const auto& pa : particles_) loaded_points.insert(pa.point);
  for (const auto& b : bodies_) {
    loaded_points.insert(b.mass_center);
    loaded_frames.insert(b.frame);
  }
  for (const auto& l : loads_) {
    (l.kind == LoadSpec::Kind::kForce ? loaded_points : loaded_frames).insert(l.target);
  }
  m.loaded_points_.assign(loaded_points.begin(), loaded_points.end());
  m.loaded_frames_.assign(loaded_frames.begin(), loaded_frames.end());
  m.has_general_fields_ = general;
  m.coordinates_ = std::move(coordinates_);
  m.speeds_ = std::move(speeds_);
  m.frames_ = std::move(frames_);
  m.points_ = std::move(points_);
  m.particles_ = std::move(particles_);
  m.bodies_ = std::move(bodies_);
  m.loads_ = std::move(loads_);
  m.slots_ = std::move(slots_);
  m.time_functions_ = std::move(time_functions_);
  m.kinematic_matrix_ = std::move(kinematic_matrix_);
  return m;
}

}  // namespace hybridtest::multibody
