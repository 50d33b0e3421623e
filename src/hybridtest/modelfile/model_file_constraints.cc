// Model files: `constraints:`, `dependent_speeds:`, `dependent_coordinates:`,
// `constraint_stabilisation:` and the check of the constraints at the initial state
// (docs/model-files.md, "Constraints"; the engine's side is multibody/constraints.h).
#include <fmt/core.h>

#include <cmath>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/expression_eval.h"
#include "hybridtest/modelfile/file_context.h"
#include "hybridtest/modelfile/names.h"
#include "hybridtest/multibody/assembly.h"

namespace hybridtest::modelfile::internal {

namespace {

std::vector<int> Components(FileContext& c, const YAML::Node& s, const std::string& kp) {
  if (!s["components"]) return {0, 1, 2};
  const YAML::Node node = s["components"];
  std::vector<int> out;
  if (!node.IsSequence()) c.in.ThrowValue(node, kp + ".components", "a list such as [x, y]");
  for (const auto& item : node) {
    const std::string v = item.IsScalar() ? item.Scalar() : "";
    if (v != "x" && v != "y" && v != "z") {
      c.in.ThrowValue(item, kp + ".components", "x, y or z (components in expressed_in)");
    }
    out.push_back(v[0] - 'x');
  }
  return out;
}

// A velocity constraint must be B(q, t) u + c(q, t): checked at random states, with the
// second difference in u, e(q, 2u) − 2 e(q, u) + e(q, 0), and the cross difference.
void CheckLinearInSpeeds(FileContext& c, const YAML::Node& node, const std::string& kp,
                         const Expression& e) {
  if (!e.Uses(Op::kSpeed)) {
    throw ConfigError(fmt::format("{} = '{}': reads no speed; a configuration constraint f(q, t) "
                                  "= 0 goes under `holonomic:`", c.Where(node, kp), node.Scalar()));
  }
  const int n = c.num_coordinates;
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> q(n), u(n), w(n), zero(n, 0.0), sum(n), twice(n);
  auto eval = [&](const std::vector<double>& speeds) {
    const Variables<double> v{0.3, q, speeds, {}, {}};
    return Evaluate(e, v);
  };
  for (int trial = 0; trial < 3; ++trial) {
    for (int k = 0; k < n; ++k) {
      q[k] = uni(rng);
      u[k] = uni(rng);
      w[k] = uni(rng);
      sum[k] = u[k] + w[k];
      twice[k] = 2.0 * u[k];
    }
    const double e0 = eval(zero), eu = eval(u), ew = eval(w);
    const double second = eval(twice) - 2.0 * eu + e0;
    const double cross = eval(sum) - eu - ew + e0;
    const double scale = std::abs(e0) + std::abs(eu) + std::abs(ew) + 1e-300;
    if (!(std::abs(second) <= 1e-9 * scale && std::abs(cross) <= 1e-9 * scale)) {
      throw ConfigError(fmt::format(
          "{} = '{}': is not linear in the speeds (e(q, 2u) − 2 e(q, u) + e(q, 0) = {:.3g} at a "
          "random state); a velocity constraint must have the form B(q, t) u + c(q, t) = 0: "
          "speeds may be multiplied by functions of q and t only (not by speeds, nor inside "
          "sin, sqrt, ...)", c.Where(node, kp), node.Scalar(), second));
    }
  }
}

// The velocity constraint `e` as coefficient fields B_j(q, t) (for the speeds it reads) and
// c(q, t), each e evaluated at a unit speed vector minus e at u = 0 (exact for an affine e).
void AddNonholonomic(FileContext& c, const std::string& name, const Expression& parsed) {
  auto e = std::make_shared<const Expression>(parsed);
  const int n = c.num_coordinates;
  auto at_speed = [e, n](int j) {
    return [e, n, j](const auto& a) {
      using J = std::decay_t<decltype(a.t)>;
      thread_local std::vector<J> speeds;
      speeds.assign(static_cast<std::size_t>(n), J(0.0));
      const Variables<J> zero{a.t, a.q, speeds, {}, {}};
      const J e0 = Evaluate(*e, zero);
      if (j < 0) return e0;
      speeds[static_cast<std::size_t>(j)] = J(1.0);
      const Variables<J> unit{a.t, a.q, speeds, {}, {}};
      return Evaluate(*e, unit) - e0;
    };
  };
  std::vector<std::pair<int, multibody::ScalarField>> coefficients;
  std::vector<bool> used(static_cast<std::size_t>(n), false);
  for (const Node& node : e->nodes())
    if (node.op == Op::kSpeed) used[static_cast<std::size_t>(node.index)] = true;
  for (int j = 0; j < n; ++j) {
    if (used[static_cast<std::size_t>(j)]) {
      coefficients.emplace_back(j, multibody::ScalarField::Function(at_speed(j)));
    }
  }
  c.builder->AddNonholonomicConstraint(name, std::move(coefficients),
                                       multibody::ScalarField::Function(at_speed(-1)));
}

std::vector<int> IndexList(FileContext& c, const YAML::Node& node, const std::string& kp,
                           Op kind) {
  std::vector<int> out;
  if (!node.IsDefined()) return out;
  if (!node.IsSequence()) c.in.ThrowValue(node, kp, "a list of names");
  for (const auto& item : node) {
    const std::string name = c.in.String(item, kp, "a name");
    const Symbol* s = c.symbols.Find(name);
    if (s == nullptr || s->kind != kind) {
      throw ConfigError(fmt::format("{} = '{}': not a {}; list names declared under {}",
                                    c.Where(item, kp), name,
                                    kind == Op::kSpeed ? "speed" : "coordinate",
                                    kind == Op::kSpeed ? "speeds:" : "coordinates:"));
    }
    out.push_back(s->index);
  }
  return out;
}

// `record_force: true|false` (default false).
bool RecordForce(FileContext& c, const YAML::Node& s, const std::string& kp) {
  const YAML::Node node = s["record_force"];
  if (!node.IsDefined()) return false;
  const std::string value = node.IsScalar() ? node.Scalar() : "";
  if (value != "true" && value != "false") {
    c.in.ThrowValue(node, kp + ".record_force", "true (write the constraint's force as journal "
                    "channels) or false");
  }
  return value == "true";
}

// The unit of the constraint's multipliers: [N] for points; for an expression, work [J] over
// the unit of f (holonomic) or power [W] over the unit of the row (nonholonomic).
std::string ForceUnit(FileContext& c, const YAML::Node& s, const std::string& kp) {
  const bool holonomic = s["holonomic"].IsDefined();
  if (!holonomic && !s["nonholonomic"].IsDefined()) return "N";
  const char* key = holonomic ? "holonomic" : "nonholonomic";
  const Dim row = c.Parse(s[key], kp + "." + key).dim();
  if (!row.known) {
    throw ConfigError(fmt::format("{}.record_force: the unit of the constraint's force cannot be "
                                  "told, because the dimension of '{}' is unknown; give its "
                                  "parameters units", c.Where(s, kp), s[key].Scalar()));
  }
  Dim force{true, {2 - row.e[0], 1 - row.e[1], (holonomic ? -2 : -3) - row.e[2]}};
  if (force == kForce) return "N";
  if (force == kMoment) return "N·m";
  return DimName(force);
}

}  // namespace

std::vector<YAML::Node> ReadConstraints(FileContext& c, const YAML::Node& root) {
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = ListItems(c.in, root["constraints"], "constraints", &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const YAML::Node& s = items[i];
    const std::string& kp = labels[i];
    c.in.RequireMapping(s, kp);
    c.in.CheckKeys(s, kp, {"name", "description", "holonomic", "nonholonomic", "coincide",
                           "velocity_zero", "of_body", "through", "components", "expressed_in",
                           "record_force"});
    const std::string name = c.in.ReadString(s, kp, "name", kp);
    if (s["name"]) CheckName(c.in, s["name"], kp + ".name", name, NameKind::kText);
    const int kinds = (s["holonomic"] ? 1 : 0) + (s["nonholonomic"] ? 1 : 0) +
                      (s["coincide"] ? 1 : 0) + (s["velocity_zero"] ? 1 : 0);
    if (kinds != 1) {
      throw ConfigError(fmt::format("{}: give exactly one of holonomic: f(q, t), nonholonomic: "
                                    "B(q, t) u + c, coincide: [P, Q] or velocity_zero: P",
                                    c.Where(s, kp)));
    }
    try {
      if (s["holonomic"]) {
        c.builder->AddHolonomicConstraint(name, c.Field(s["holonomic"], kp + ".holonomic"));
      } else if (s["nonholonomic"]) {
        const Expression e = c.Parse(s["nonholonomic"], kp + ".nonholonomic");
        if (e.Uses(Op::kSlot) || e.Uses(Op::kState) || e.Uses(Op::kTimeFunction) ||
            e.Uses(Op::kVelocity) || e.Uses(Op::kAngularVelocity)) {
          throw ConfigError(fmt::format("{} = '{}': may use t, coordinates, speeds and "
                                        "parameters only", c.Where(s["nonholonomic"],
                                        kp + ".nonholonomic"), s["nonholonomic"].Scalar()));
        }
        CheckLinearInSpeeds(c, s["nonholonomic"], kp + ".nonholonomic", e);
        AddNonholonomic(c, name, e);
      } else {
        const multibody::FrameId E = s["expressed_in"]
            ? c.Frame(s["expressed_in"], kp + ".expressed_in") : c.frames.at("N");
        const std::vector<int> comps = Components(c, s, kp);
        if (s["coincide"]) {
          const YAML::Node pq = s["coincide"];
          if (!pq.IsSequence() || pq.size() != 2) {
            c.in.ThrowValue(pq, kp + ".coincide", "two point names [P, Q]");
          }
          c.builder->AddCoincidenceConstraint(name, c.Point(pq[0], kp + ".coincide[0]"),
                                              c.Point(pq[1], kp + ".coincide[1]"), E, comps);
        } else {
          multibody::FrameId body{-1};
          multibody::PointId through{-1};
          if (s["of_body"]) {
            body = c.Frame(s["of_body"], kp + ".of_body");
            through = c.Point(c.Require(s, "through", kp, "a point fixed in of_body (e.g. the "
                                        "wheel centre)"), kp + ".through");
          }
          c.builder->AddVelocityConstraint(name, c.Point(s["velocity_zero"], kp + ".velocity_zero"),
                                           E, comps, body, through);
        }
      }
      if (RecordForce(c, s, kp)) c.builder->RecordConstraintForce(name, ForceUnit(c, s, kp));
    } catch (const ModelError& e) {
      throw ConfigError(fmt::format("{}: {}", c.Where(s, kp), e.what()));
    }
  }
  if (items.empty()) {
    for (const char* key : {"dependent_speeds", "dependent_coordinates", "constraint_stabilisation"}) {
      if (root[key]) {
        throw ConfigError(fmt::format("{}: the model has no constraints; remove it",
                                      c.Where(root[key], key)));
      }
    }
    return items;
  }
  multibody::ConstraintOptions options;
  options.dependent_speeds = IndexList(c, root["dependent_speeds"], "dependent_speeds", Op::kSpeed);
  options.dependent_coordinates =
      IndexList(c, root["dependent_coordinates"], "dependent_coordinates", Op::kCoordinate);
  if (root["constraint_stabilisation"]) {
    options.stabilisation_time_constant = c.Constant(
        root["constraint_stabilisation"], "constraint_stabilisation",
        "a time constant in s (0: off)", Dim{true, {0, 0, 1}});
  }
  try {
    c.builder->SetConstraintOptions(options);
  } catch (const ModelError& e) {
    throw ConfigError(fmt::format("{}: {}", c.Where(root["constraint_stabilisation"],
                                                    "constraint_stabilisation"), e.what()));
  }
  return items;
}

void CheckConstraintsAtInitialState(const FileContext& c, const YAML::Node& root,
                                    const std::vector<YAML::Node>& items,
                                    const multibody::Model& model) {
  if (!model.has_constraints()) return;
  const Eigen::VectorXd x0 = model.initial_state();
  const multibody::ConstraintResiduals before = multibody::CalcConstraintResiduals(model, 0.0, x0);
  try {
    (void)multibody::AssembleState(model, 0.0, x0);
  } catch (const ModelError& e) {
    const std::string what = e.what();
    if (what.find("dependent speeds") != std::string::npos && root["dependent_speeds"]) {
      throw ConfigError(fmt::format("{}: {}", c.Where(root["dependent_speeds"], "dependent_speeds"),
                                    what));
    }
    const int row = before.worst_row >= 0 ? before.worst_row : 0;
    const int k = model.constraint_rows()[static_cast<std::size_t>(row)].constraint;
    throw ConfigError(fmt::format(
        "{}: at the initial state (the coordinates' and speeds' `initial:` values, default 0): "
        "{}", c.Where(items[static_cast<std::size_t>(k)], fmt::format("constraints[{}]", k)),
        what));
  }
}

}  // namespace hybridtest::modelfile::internal
