// See rod_setup.h.
#include "hybridtest/substructures/rod_setup.h"

#include <Eigen/Dense>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {
namespace {

double SmallestSingularValue(const Eigen::MatrixXd& j) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(j).singularValues().minCoeff();
}

std::string Point(const Eigen::VectorXd& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += fmt::format("{}{:.6g}", i ? ", " : "", v(i));
  return s + "]";
}

}  // namespace

RodSetup::RodSetup(RodGeometry geometry) : g_(std::move(geometry)) {
  const auto dim = g_.directions.rows();
  const auto m = g_.directions.cols(), n = g_.bases.cols();
  if (dim != 2 && dim != 3) {
    throw ConfigError(fmt::format("directions: {} coordinates; expected 2 ([x, y]) or 3 "
                                  "([x, y, z]) in the setup's frame", dim));
  }
  if (m < 1 || n < 1) {
    throw ConfigError(fmt::format("{} slot directions and {} actuators: expected at least one of "
                                  "each", m, n));
  }
  if (g_.bases.rows() != dim || g_.attachments.rows() != dim || g_.attachments.cols() != n) {
    throw ConfigError(fmt::format("actuators: every base and attach point needs {} coordinates "
                                  "(as the slot directions), [m]", dim));
  }
  if (g_.p0.size() != n || g_.load_cell_zero.size() != n) {
    throw ConfigError(fmt::format("p0 has {} values and load_cell_zero {} for {} actuators: give "
                                  "one of each per actuator", g_.p0.size(),
                                  g_.load_cell_zero.size(), n));
  }
  if (!g_.p0.allFinite() || !g_.load_cell_zero.allFinite()) {
    throw ConfigError("p0 and load_cell_zero must be finite");
  }
  const int rot = g_.rotation_slot;
  if (rot >= m || rot < -1) {
    throw ConfigError(fmt::format("rotation slot {} of {} slots", rot + 1, m));
  }
  if (rot >= 0) {
    g_.directions.col(rot).setZero();
    if (g_.rotation_point.size() != dim || !g_.rotation_point.allFinite()) {
      throw ConfigError(fmt::format("directions[{}].rotation_about: expected a finite point of {} "
                                    "coordinates in m", rot, dim));
    }
    if (dim == 3) {
      if (g_.rotation_axis.size() != 3 || !g_.rotation_axis.allFinite() ||
          g_.rotation_axis.norm() == 0.0) {
        throw ConfigError(fmt::format("directions[{}].axis: expected a finite, non-zero direction "
                                      "[ax, ay, az] of the rotation axis", rot));
      }
      g_.rotation_axis.normalize();
    } else {
      g_.rotation_axis = Eigen::Vector3d(0.0, 0.0, 1.0);
    }
  }
  for (Eigen::Index i = 0; i < m; ++i) {
    if (i == rot) continue;
    if (!g_.directions.col(i).allFinite() || g_.directions.col(i).norm() == 0.0) {
      throw ConfigError(fmt::format("directions[{}] = {}: expected a finite, non-zero direction "
                                    "(a unit vector for a slot that is the specimen's "
                                    "displacement along it)", i, Point(g_.directions.col(i))));
    }
  }
  l0_.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!g_.bases.col(k).allFinite() || !g_.attachments.col(k).allFinite()) {
      throw ConfigError(fmt::format("actuators[{}]: base and attach must be finite points in m",
                                    k));
    }
    l0_(k) = (g_.attachments.col(k) - g_.bases.col(k)).norm();
    if (!(l0_(k) >= kMinRodLength)) {
      throw ConfigError(fmt::format("actuators[{}]: base {} and attach {} are {} m apart; a rod "
                                    "needs a length of at least {} m (give the pin positions "
                                    "in m)", k, Point(g_.bases.col(k)),
                                    Point(g_.attachments.col(k)), l0_(k), kMinRodLength));
    }
  }
  t0_ = CalcJacobian(Eigen::VectorXd::Zero(m));
  Eigen::FullPivLU<Eigen::MatrixXd> lu(t0_);
  if (lu.rank() < m) {
    throw ConfigError(fmt::format("the rods' axes projected on the slot directions (J(0), {} × "
                                  "{}) have rank {}: the actuators cannot tell the {} slots "
                                  "apart; turn a rod or a slot direction so that every slot "
                                  "moves some rod along its axis", n, m, lu.rank(), m));
  }
}

Eigen::VectorXd RodSetup::Cross(const Eigen::VectorXd& v) const {
  if (v.size() == 2) return Eigen::Vector2d(-v(1), v(0));
  return Eigen::Vector3d(g_.rotation_axis).cross(Eigen::Vector3d(v));
}

void RodSetup::CalcRods(const Eigen::Ref<const Eigen::VectorXd>& d, Eigen::MatrixXd& rods,
                        Eigen::VectorXd& lengths, Eigen::MatrixXd& arms) const {
  const Eigen::VectorXd shift = g_.directions * d;  // the translations (the rotation's column is 0)
  rods = g_.attachments - g_.bases;
  rods.colwise() += shift;
  arms = Eigen::MatrixXd::Zero(g_.dimension(), g_.num_actuators());
  if (g_.rotation_slot >= 0) {
    // Rodrigues: R v = v cos θ + (a × v) sin θ + a (a · v)(1 − cos θ); in 2-D a = z.
    const double theta = d(g_.rotation_slot), c = std::cos(theta), s = std::sin(theta);
    for (Eigen::Index k = 0; k < rods.cols(); ++k) {
      const Eigen::VectorXd v = g_.attachments.col(k) - g_.rotation_point;
      Eigen::VectorXd w = c * v + s * Cross(v);
      if (v.size() == 3) w += (1.0 - c) * g_.rotation_axis.dot(v) * g_.rotation_axis;
      arms.col(k) = w;
      rods.col(k) += w - v;
    }
  }
  lengths = rods.colwise().norm().transpose();
  for (Eigen::Index k = 0; k < lengths.size(); ++k) {
    if (!(lengths(k) >= kMinRodLength)) {
      throw Error(fmt::format("large-displacement setup: at slot displacements {} rod {} has "
                              "length {} m; its axis is undefined", Point(d), k + 1,
                              lengths(k)));
    }
  }
}

Eigen::MatrixXd RodSetup::SlotGradients(const Eigen::VectorXd& arm) const {
  Eigen::MatrixXd g = g_.directions;
  if (g_.rotation_slot >= 0) g.col(g_.rotation_slot) = Cross(arm);
  return g;
}

Eigen::VectorXd RodSetup::CalcLengths(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  Eigen::MatrixXd rods, arms;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths, arms);
  return lengths;
}

void RodSetup::CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                            Eigen::Ref<Eigen::VectorXd> a) const {
  a = g_.p0 + (CalcLengths(d) - l0_);
}

Eigen::MatrixXd RodSetup::CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  Eigen::MatrixXd rods, arms;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths, arms);
  if (g_.rotation_slot < 0) {
    // J_ki = n_k · e_i with n_k = rod_k / ℓ_k.
    return (rods.transpose() * g_.directions).array().colwise() / lengths.array();
  }
  Eigen::MatrixXd j(rods.cols(), g_.num_slots());
  for (Eigen::Index k = 0; k < rods.cols(); ++k) {
    j.row(k) = (SlotGradients(arms.col(k)).transpose() * rods.col(k)).transpose() / lengths(k);
  }
  return j;
}

Eigen::MatrixXd RodSetup::CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& d,
                                                 const Eigen::Ref<const Eigen::VectorXd>& f) const {
  Eigen::MatrixXd rods, arms;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths, arms);
  const auto m = g_.directions.cols();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index k = 0; k < lengths.size(); ++k) {
    // gᵀ (I − n nᵀ) g / ℓ = (gᵀg − (gᵀn)(gᵀn)ᵀ) / ℓ, plus n · ∂²p/∂θ² for the rotation.
    const Eigen::MatrixXd grad = SlotGradients(arms.col(k));
    const Eigen::VectorXd n = rods.col(k) / lengths(k);
    const Eigen::VectorXd gtn = grad.transpose() * n;
    g += f(k) / lengths(k) * (grad.transpose() * grad - gtn * gtn.transpose());
    if (g_.rotation_slot >= 0) {
      const int r = g_.rotation_slot;
      g(r, r) += f(k) * n.dot(Cross(Cross(arms.col(k))));
    }
  }
  return g;
}

double RodSetup::lever_arm(int k) const {
  if (g_.rotation_slot < 0) return 0.0;
  const Eigen::VectorXd v = g_.attachments.col(k) - g_.rotation_point;
  if (v.size() == 2) return v.norm();
  return (v - g_.rotation_axis.dot(v) * g_.rotation_axis).norm();
}

double RodSetup::CommandStepBound(int k) const {
  const auto m = g_.directions.cols();
  if (m > 12) return g_.directions.colwise().norm().sum() + lever_arm(k);
  double worst = 0.0;
  // Sign vectors with s_0 = +1 (−s gives the same norm).
  for (long bits = 0; bits < (1L << (m - 1)); ++bits) {
    Eigen::VectorXd v = g_.directions.col(0);
    for (Eigen::Index i = 1; i < m; ++i) {
      v += ((bits >> (i - 1)) & 1L ? -1.0 : 1.0) * g_.directions.col(i);
    }
    worst = std::max(worst, v.norm());
  }
  return worst + lever_arm(k);
}

std::string RodSetup::Describe() const {
  std::string lengths;
  for (Eigen::Index k = 0; k < l0_.size(); ++k) {
    lengths += fmt::format("{}{:.4g}", k ? ", " : "", l0_(k));
  }
  const int rotations = g_.rotation_slot >= 0 ? 1 : 0;
  return fmt::format("large-displacement setup: {} rods (L0 = {} m), {} translational and {} "
                     "rotational slots in {}-D", num_actuators(), lengths,
                     num_slots() - rotations, rotations, g_.dimension());
}

std::optional<NearSingularPoint> FindNearSingular(const RodSetup& setup,
                                                  const Eigen::VectorXd& half_widths,
                                                  const std::vector<transfer::SafetyLimits>& limits,
                                                  double threshold) {
  const int m = setup.num_slots(), n = setup.num_actuators();
  if (half_widths.size() != m || static_cast<int>(limits.size()) != n) {
    throw Error("FindNearSingular: one half-width per slot and one set of limits per actuator");
  }
  // Points per slot: odd (the axes and 0 included), at least 5, about 4,000 in all.
  int per = static_cast<int>(std::floor(std::pow(4000.0, 1.0 / m)));
  per = std::max(5, per % 2 == 0 ? per - 1 : per);
  const double reference = SmallestSingularValue(setup.linearisation());
  Eigen::VectorXi index = Eigen::VectorXi::Zero(m);
  Eigen::VectorXd d(m), a(n);
  while (true) {
    for (int i = 0; i < m; ++i) {
      d(i) = half_widths(i) * (2.0 * index(i) / (per - 1) - 1.0);
    }
    bool reachable = true;
    try {
      setup.CalcCommands(d, a);
      for (int k = 0; k < n && reachable; ++k) {
        const auto& l = limits[static_cast<std::size_t>(k)];
        reachable = a(k) >= l.stroke_min && a(k) <= l.stroke_max;
      }
      if (reachable) {
        const double ratio = SmallestSingularValue(setup.CalcJacobian(d)) / reference;
        if (ratio < threshold) return NearSingularPoint{d, ratio};
      }
    } catch (const Error&) {  // a rod of (nearly) zero length: singular wherever reachable
      return NearSingularPoint{d, 0.0};
    }
    int i = 0;
    while (i < m && ++index(i) == per) index(i++) = 0;
    if (i == m) break;
  }
  return std::nullopt;
}

}  // namespace hybridtest::substructures
