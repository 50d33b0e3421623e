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
    throw ConfigError(fmt::format("slots: directions of {} coordinates; expected 2 ([x, y]) or 3 "
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
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!g_.directions.col(i).allFinite() || g_.directions.col(i).norm() == 0.0) {
      throw ConfigError(fmt::format("slots[{}] = {}: expected a finite, non-zero direction "
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

void RodSetup::CalcRods(const Eigen::Ref<const Eigen::VectorXd>& d, Eigen::MatrixXd& rods,
                        Eigen::VectorXd& lengths) const {
  const Eigen::VectorXd shift = g_.directions * d;  // D(d)
  rods = g_.attachments - g_.bases;
  rods.colwise() += shift;
  lengths = rods.colwise().norm().transpose();
  for (Eigen::Index k = 0; k < lengths.size(); ++k) {
    if (!(lengths(k) >= kMinRodLength)) {
      throw Error(fmt::format("large-displacement setup: at slot displacements {} m rod {} has "
                              "length {} m; its axis is undefined", Point(d), k + 1,
                              lengths(k)));
    }
  }
}

Eigen::VectorXd RodSetup::CalcLengths(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  Eigen::MatrixXd rods;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths);
  return lengths;
}

void RodSetup::CalcCommands(const Eigen::Ref<const Eigen::VectorXd>& d,
                            Eigen::Ref<Eigen::VectorXd> a) const {
  a = g_.p0 + (CalcLengths(d) - l0_);
}

Eigen::MatrixXd RodSetup::CalcJacobian(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  Eigen::MatrixXd rods;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths);
  // J_ki = n_k · e_i with n_k = rod_k / ℓ_k.
  return (rods.transpose() * g_.directions).array().colwise() / lengths.array();
}

Eigen::MatrixXd RodSetup::CalcGeometricStiffness(const Eigen::Ref<const Eigen::VectorXd>& d,
                                                 const Eigen::Ref<const Eigen::VectorXd>& f) const {
  Eigen::MatrixXd rods;
  Eigen::VectorXd lengths;
  CalcRods(d, rods, lengths);
  const auto m = g_.directions.cols();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(m, m);
  const Eigen::MatrixXd ete = g_.directions.transpose() * g_.directions;  // (m × m)
  for (Eigen::Index k = 0; k < lengths.size(); ++k) {
    // Eᵀ (I − n nᵀ) E / ℓ = (EᵀE − (Eᵀn)(Eᵀn)ᵀ) / ℓ
    const Eigen::VectorXd etn = g_.directions.transpose() * (rods.col(k) / lengths(k));
    g += f(k) / lengths(k) * (ete - etn * etn.transpose());
  }
  return g;
}

double RodSetup::CommandStepBound(int /*k*/) const {
  const auto m = g_.directions.cols();
  if (m > 12) return g_.directions.colwise().norm().sum();
  double worst = 0.0;
  // Sign vectors with s_0 = +1 (−s gives the same norm).
  for (long bits = 0; bits < (1L << (m - 1)); ++bits) {
    Eigen::VectorXd v = g_.directions.col(0);
    for (Eigen::Index i = 1; i < m; ++i) {
      v += ((bits >> (i - 1)) & 1L ? -1.0 : 1.0) * g_.directions.col(i);
    }
    worst = std::max(worst, v.norm());
  }
  return worst;
}

std::string RodSetup::Describe() const {
  std::string lengths;
  for (Eigen::Index k = 0; k < l0_.size(); ++k) {
    lengths += fmt::format("{}{:.4g}", k ? ", " : "", l0_(k));
  }
  return fmt::format("large-displacement setup: {} rods (L0 = {} m), {} translational slots in "
                     "{}-D", num_actuators(), lengths, num_slots(), g_.dimension());
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
