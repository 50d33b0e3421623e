// ModelBuilder's constraint declarations and the constraint rows Build() derives from them.
// See constraint_spec.h.
#include <fmt/core.h>

#include <cmath>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/model.h"

namespace hybridtest::multibody {

namespace {
void CheckComponents(const std::vector<int>& components, const std::string& what) {
  std::set<int> seen;
  if (components.empty()) throw ModelError(what + ": no components; give x, y and/or z");
  for (int c : components) {
    if (c < 0 || c > 2 || !seen.insert(c).second) {
      throw ModelError(fmt::format("{}: component {} is not one of x, y, z (0, 1, 2) or is "
                                   "given twice", what, c));
    }
  }
}
}  // namespace

void ModelBuilder::AddHolonomicConstraint(std::string name, ScalarField f) {
  CheckField(f, "constraint '" + name + "'");
  ConstraintSpec c;
  c.name = std::move(name);
  c.kind = ConstraintSpec::Kind::kHolonomic;
  c.field = std::move(f);
  elements_.constraints.push_back(std::move(c));
}

void ModelBuilder::AddNonholonomicConstraint(std::string name,
                                             std::vector<std::pair<int, ScalarField>> coefficients,
                                             ScalarField constant) {
  const std::string what = "constraint '" + name + "'";
  const int n = static_cast<int>(elements_.coordinates.size());
  for (const auto& [j, field] : coefficients) {
    if (j < 0 || j >= n) {
      throw ModelError(fmt::format("{}: speed index {} out of range (n = {})", what, j, n));
    }
    CheckField(field, what);
  }
  CheckField(constant, what);
  ConstraintSpec c;
  c.name = std::move(name);
  c.kind = ConstraintSpec::Kind::kNonholonomic;
  c.coefficients = std::move(coefficients);
  c.constant = std::move(constant);
  elements_.constraints.push_back(std::move(c));
}

void ModelBuilder::AddCoincidenceConstraint(std::string name, PointId P, PointId Q,
                                            FrameId expressed_in, std::vector<int> components) {
  const std::string what = "constraint '" + name + "'";
  CheckPoint(P, what);
  CheckPoint(Q, what);
  CheckFrame(expressed_in, what);
  CheckComponents(components, what);
  ConstraintSpec c;
  c.name = std::move(name);
  c.kind = ConstraintSpec::Kind::kCoincident;
  c.point = P.index;
  c.other = Q.index;
  c.expressed_in = expressed_in.index;
  c.components = std::move(components);
  elements_.constraints.push_back(std::move(c));
}

void ModelBuilder::AddVelocityConstraint(std::string name, PointId P, FrameId expressed_in,
                                         std::vector<int> components, FrameId body,
                                         PointId body_point) {
  const std::string what = "constraint '" + name + "'";
  CheckPoint(P, what);
  CheckFrame(expressed_in, what);
  CheckComponents(components, what);
  if (body.index >= 0) {
    CheckFrame(body, what);
    CheckPoint(body_point, what + " (the point fixed in the body)");
  }
  ConstraintSpec c;
  c.name = std::move(name);
  c.kind = ConstraintSpec::Kind::kVelocity;
  c.point = P.index;
  c.body = body.index;
  c.body_point = body.index >= 0 ? body_point.index : -1;
  c.expressed_in = expressed_in.index;
  c.components = std::move(components);
  elements_.constraints.push_back(std::move(c));
}

void ModelBuilder::RecordConstraintForce(const std::string& name, std::string force_unit) {
  for (ConstraintSpec& c : elements_.constraints) {
    if (c.name == name) {
      c.record_force = true;
      c.force_unit = std::move(force_unit);
      return;
    }
  }
  throw ModelError(fmt::format("RecordConstraintForce: no constraint is named '{}'; add it "
                               "first", name));
}

void ModelBuilder::SetConstraintOptions(ConstraintOptions options) {
  if (!(options.stabilisation_time_constant >= 0.0) ||
      !std::isfinite(options.stabilisation_time_constant)) {
    throw ModelError(fmt::format("constraint stabilisation time constant = {}: expected a "
                                 "non-negative time in s (0: off)",
                                 options.stabilisation_time_constant));
  }
  if (!(options.tolerance > 0.0)) {
    throw ModelError(fmt::format("constraint tolerance = {}: expected a positive residual",
                                 options.tolerance));
  }
  elements_.constraint_options = std::move(options);
}

void ModelBuilder::SetInitialState(std::vector<double> q, std::vector<double> u) {
  const std::size_t n = elements_.coordinates.size();
  if ((!q.empty() && q.size() != n) || (!u.empty() && u.size() != n)) {
    throw ModelError(fmt::format("initial state: {} coordinates and {} speeds given; the model "
                                 "has n = {}", q.size(), u.size(), n));
  }
  elements_.initial_q = std::move(q);
  elements_.initial_u = std::move(u);
}

Eigen::VectorXd Model::initial_state() const {
  const int n = num_coordinates();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_states());
  for (std::size_t k = 0; k < elements_.initial_q.size(); ++k) x(static_cast<Eigen::Index>(k)) = elements_.initial_q[k];
  for (std::size_t k = 0; k < elements_.initial_u.size(); ++k) x(n + static_cast<Eigen::Index>(k)) = elements_.initial_u[k];
  for (int k = 0; k < num_extra_states(); ++k) x(2 * n + k) = elements_.extra_states[k].initial;
  return x;
}

namespace internal {

void CompileConstraintRows(const ModelElements& e, std::vector<ConstraintRow>& rows,
                           int& num_holonomic) {
  rows.clear();
  num_holonomic = 0;
  for (int i = 0; i < static_cast<int>(e.constraints.size()); ++i) {
    const ConstraintSpec& c = e.constraints[static_cast<std::size_t>(i)];
    for (int r = 0; r < c.num_rows(); ++r) {
      rows.push_back({i, c.components.empty() ? 0 : c.components[static_cast<std::size_t>(r)],
                      c.holonomic()});
      num_holonomic += c.holonomic() ? 1 : 0;
    }
  }
  const int n = static_cast<int>(e.coordinates.size());
  const int m = static_cast<int>(rows.size());
  if (m >= n && m > 0) {
    throw ModelError(fmt::format("the constraints give {} rows for {} speeds; at least one speed "
                                 "must stay independent (remove redundant constraints)", m, n));
  }
  auto check_set = [&](const std::vector<int>& set, int want, const char* what) {
    if (set.empty()) return;
    if (static_cast<int>(set.size()) != want) {
      throw ModelError(fmt::format("{} dependent {} given, but the constraints have {} {}rows; "
                                   "give one per row (or none: then they are picked by "
                                   "pivoting)", set.size(), what, want,
                                   std::string(what) == "coordinates" ? "holonomic " : ""));
    }
    std::set<int> seen;
    for (int j : set) {
      if (j < 0 || j >= n || !seen.insert(j).second) {
        throw ModelError(fmt::format("dependent {}: index {} is out of range (n = {}) or given "
                                     "twice", what, j, n));
      }
    }
  };
  check_set(e.constraint_options.dependent_speeds, m, "speeds");
  check_set(e.constraint_options.dependent_coordinates, num_holonomic, "coordinates");
}

}  // namespace internal
}  // namespace hybridtest::multibody
