// See delay_stability.h.
#include "hybridtest/runner/delay_stability.h"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/derivatives.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/slot_info.h"
#include "hybridtest/schemes/step_control.h"

namespace hybridtest::runner {
namespace {

using cd = std::complex<double>;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct CoupledCrossing {
  double delay = std::numeric_limits<double>::infinity();  // [s]
  double hz = 0.0;
};

// The i-th largest eigenvalue modulus of L(ω) = KD_B P(jω)⁻¹ b_B, P = −ω² I − jω Fu + Kq0, and
// the eigenvalues: sorted by modulus, each a continuous function of ω.
Eigen::VectorXcd SortedEigenvalues(const Eigen::MatrixXd& Fu, const Eigen::MatrixXd& Kq0,
                                   const Eigen::MatrixXd& KD_B, const Eigen::MatrixXd& b_B,
                                   double w) {
  const auto n = Fu.rows();
  const Eigen::MatrixXcd P = (-w * w) * Eigen::MatrixXcd::Identity(n, n) -
                             cd(0.0, w) * Fu.cast<cd>() + Kq0.cast<cd>();
  const Eigen::MatrixXcd L = KD_B.cast<cd>() * P.partialPivLu().solve(b_B.cast<cd>());
  Eigen::VectorXcd e = Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(L, false).eigenvalues();
  std::sort(e.data(), e.data() + e.size(),
            [](const cd& a, const cd& c) { return std::abs(a) > std::abs(c); });
  return e;
}

// The smallest common delay τ of every slot of a block at which det(I − e^{−jωτ} L(jω)) = 0
// for some ω: an eigenvalue λ of L of modulus 1, τ = (arg λ mod 2π)/ω. For one slot this is
// the scalar check below (L = k g).
CoupledCrossing CoupledCriticalDelay(const Eigen::MatrixXd& Fu, const Eigen::MatrixXd& Kq0,
                                     const Eigen::MatrixXd& KD_B, const Eigen::MatrixXd& b_B,
                                     double w_lo, double w_hi, int points) {
  CoupledCrossing best;
  const auto mb = KD_B.rows();
  auto excess = [&](double w, Eigen::Index i) {
    return std::abs(SortedEigenvalues(Fu, Kq0, KD_B, b_B, w)(i)) - 1.0;
  };
  Eigen::VectorXd e_prev(mb);
  for (Eigen::Index i = 0; i < mb; ++i) e_prev(i) = excess(w_lo, i);
  double w_prev = w_lo;
  for (int p = 1; p <= points; ++p) {
    const double w = w_lo * std::pow(w_hi / w_lo, static_cast<double>(p) / points);
    const Eigen::VectorXcd ev = SortedEigenvalues(Fu, Kq0, KD_B, b_B, w);
    for (Eigen::Index i = 0; i < mb; ++i) {
      const double e = std::abs(ev(i)) - 1.0;
      if ((e_prev(i) < 0.0) != (e < 0.0)) {
        double a = w_prev, c = w;  // bisection on |λ_i| − 1
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (a + c);
          if ((excess(mid, i) < 0.0) == (e_prev(i) < 0.0)) a = mid; else c = mid;
        }
        const double wc = 0.5 * (a + c);
        double phase = std::arg(SortedEigenvalues(Fu, Kq0, KD_B, b_B, wc)(i));
        if (phase < 0.0) phase += kTwoPi;
        if (phase / wc < best.delay) best = {phase / wc, wc / kTwoPi};
      }
      e_prev(i) = e;
    }
    w_prev = w;
  }
  return best;
}

}  // namespace

std::vector<SlotDelayMargin> CheckDelayStability(const Session& session) {
  const multibody::Model& model = session.model();
  const io::RunSpec& spec = session.spec();
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  const auto& subs = session.substructures();
  const SlotMap& map = session.slot_map();
  // Every slot's K0 (the slot map: a substructure of several slots gives its K0 matrix; a
  // slot of unknown K0 counts as 0). K: the coupled K0 (m × m), or none when every block is
  // one slot (then r_j = k_j d_j).
  std::vector<std::vector<int>> slot_of;
  for (const SlotMap::Block& b : map.substructures) slot_of.push_back(b.slots);
  const schemes::SlotInfo info = SlotInfoOf(subs, slot_of, m);
  Eigen::VectorXd k = info.k0;
  for (int j = 0; j < m; ++j) {
    if (!std::isfinite(k(j))) k(j) = 0.0;
  }
  Eigen::MatrixXd K = info.k0_matrix;
  for (Eigen::Index i = 0; i < K.rows(); ++i) {
    for (Eigen::Index j = 0; j < K.cols(); ++j) {
      if (!std::isfinite(K(i, j))) K(i, j) = 0.0;
    }
  }
  const bool coupled = K.size() > 0;
  // The linearisation at x_0: J (r fixed), b = ∂u̇/∂r (affine in r: one difference is exact),
  // D = ∂d/∂q.
  multibody::Data<double> data(model);
  Eigen::VectorXd d0(m), q_scratch(n), dp(m), dm(m);
  multibody::CalcSlotDisplacements<double>(model, data, 0.0, spec.x0.head(n), d0);
  const Eigen::VectorXd r0 = k.cwiseProduct(d0);
  const auto nx = spec.x0.size();
  Eigen::MatrixXd J(nx, nx);
  multibody::DerivativeWorkspace ws(model);
  multibody::CalcStateJacobian(model, ws, 0.0, spec.x0, r0, J);
  Eigen::VectorXd f0(nx), f1(nx);
  multibody::CalcStateDerivative<double>(model, data, 0.0, spec.x0, r0, f0);
  Eigen::MatrixXd b(n, m);
  for (int j = 0; j < m; ++j) {
    Eigen::VectorXd r = r0;
    r(j) += 1.0;
    multibody::CalcStateDerivative<double>(model, data, 0.0, spec.x0, r, f1);
    b.col(j) = (f1 - f0).segment(n, n);
  }
  Eigen::MatrixXd D(m, n);
  schemes::CalcSlotJacobian(model, data, 0.0, spec.x0.head(n), D, q_scratch, dp, dm);
  const Eigen::MatrixXd Fq = J.block(n, 0, n, n), Fu = J.block(n, n, n, n);
  const double dt = spec.scheme.dt;

  // The force of slot j as a function of q: r_j = kd_j q (k_j d_j, or K_j· D when coupled).
  Eigen::MatrixXd KD;
  if (coupled) KD = K * D;

  // A block of several slots (a specimen on several actuators): every one of its slots delayed
  // together, r_B = K_B· D q(t − τ) (the coupled loop, computed once per block).
  std::vector<CoupledCrossing> block_crossing(map.substructures.size());
  std::vector<bool> block_done(map.substructures.size(), false);
  const double w_lo = 1e-2, w_hi = std::numbers::pi / dt;
  const int points = 20000;

  std::vector<SlotDelayMargin> out;
  for (int s = 0; s < m; ++s) {
    const SlotMap::Slot& slot = map.slots[static_cast<std::size_t>(s)];
    const substructures::Substructure& sub = *subs[static_cast<std::size_t>(slot.substructure)];
    if (!map.block_of(s).physical) continue;
    SlotDelayMargin margin;
    margin.slot = slot.name;
    margin.substructure = map.block_of(s).name;
    margin.k0 = k(s);
    const std::vector<int>& together = map.block_of(s).slots;
    if (coupled && together.size() > 1) {
      const auto b_index = static_cast<std::size_t>(slot.substructure);
      if (!block_done[b_index]) {
        Eigen::MatrixXd Kq0 = -Fq;
        for (int j = 0; j < m; ++j) {
          if (std::find(together.begin(), together.end(), j) == together.end()) {
            Kq0 -= b.col(j) * KD.row(j);
          }
        }
        const auto mb = static_cast<Eigen::Index>(together.size());
        Eigen::MatrixXd KD_B(mb, n), b_B(n, mb);
        for (Eigen::Index i = 0; i < mb; ++i) {
          KD_B.row(i) = KD.row(together[static_cast<std::size_t>(i)]);
          b_B.col(i) = b.col(together[static_cast<std::size_t>(i)]);
        }
        block_crossing[b_index] = CoupledCriticalDelay(Fu, Kq0, KD_B, b_B, w_lo, w_hi, points);
        block_done[b_index] = true;
      }
      margin.critical_delay = block_crossing[b_index].delay;
      margin.crossing_hz = block_crossing[b_index].hz;
      margin.delayed_together = static_cast<int>(together.size());
    }
    // The undelayed slots stiffen the model; slot s's force is the delayed one.
    Eigen::MatrixXd Kq = -Fq;
    for (int j = 0; j < m; ++j) {
      if (j == s) continue;
      if (coupled) {
        Kq -= b.col(j) * KD.row(j);
      } else {
        Kq -= b.col(j) * k(j) * D.row(j);
      }
    }
    auto kg = [&](double w) {
      Eigen::MatrixXcd P = (-w * w) * Eigen::MatrixXcd::Identity(n, n) -
                           cd(0.0, w) * Fu.cast<cd>() + Kq.cast<cd>();
      const Eigen::VectorXcd y = P.partialPivLu().solve(b.col(s).cast<cd>());
      if (coupled) return (KD.row(s).cast<cd>() * y)(0);
      return k(s) * (D.row(s).cast<cd>() * y)(0);
    };
    // Scan ω (log-spaced up to the Nyquist frequency of the step) for |k g| = 1.
    double w_prev = w_lo, e_prev = std::abs(kg(w_lo)) - 1.0;
    for (int i = 1; i <= points && margin.k0 > 0.0 && margin.delayed_together == 1; ++i) {
      const double w = w_lo * std::pow(w_hi / w_lo, static_cast<double>(i) / points);
      const double e = std::abs(kg(w)) - 1.0;
      if ((e_prev < 0.0) != (e < 0.0)) {
        double a = w_prev, c = w;  // bisection on |k g| − 1
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (a + c);
          if ((std::abs(kg(mid)) - 1.0 < 0.0) == (e_prev < 0.0)) a = mid; else c = mid;
        }
        const double wc = 0.5 * (a + c);
        double phase = std::arg(kg(wc));
        if (phase < 0.0) phase += kTwoPi;
        const double tau = phase / wc;
        if (tau < margin.critical_delay) {
          margin.critical_delay = tau;
          margin.crossing_hz = wc / kTwoPi;
        }
      }
      w_prev = w;
      e_prev = e;
    }
    // The plant's delay, as the substructure's transfer system knows it (every actuator).
    const transfer::TransferSystem* t = sub.transfer_system();
    const double wc = std::isfinite(margin.critical_delay) ? kTwoPi * margin.crossing_hz
                                                            : kTwoPi * 1.0;
    if (const auto delay = t != nullptr ? t->PhaseDelay(wc, dt) : std::nullopt) {
      margin.known_plant = true;
      margin.plant_delay = *delay;
      margin.compensation = t->compensated_delay();
      margin.remaining_delay = std::max(0.0, margin.plant_delay - margin.compensation);
    }
    out.push_back(margin);
  }
  return out;
}

std::string Describe(const SlotDelayMargin& g) {
  const std::string together =
      g.delayed_together > 1
          ? fmt::format(", {} slots of {} delayed together", g.delayed_together, g.substructure)
          : std::string();
  const std::string critical =
      std::isfinite(g.critical_delay)
          ? fmt::format("critical delay {:.3f} ms (at {:.2f} Hz{})", 1e3 * g.critical_delay,
                        g.crossing_hz, together)
          : fmt::format("no critical delay (stable for any delay{})", together);
  if (!g.known_plant) {
    return fmt::format("slot {}: K0 = {:.6g} N/m, {}; the transfer's delay is not known here",
                       g.slot, g.k0, critical);
  }
  return fmt::format("slot {}: K0 = {:.6g} N/m, {}; plant delay {:.3f} ms, compensated {:.3f} "
                     "ms, remaining {:.3f} ms", g.slot, g.k0, critical, 1e3 * g.plant_delay,
                     1e3 * g.compensation, 1e3 * g.remaining_delay);
}

void RefuseUnstable(const Session& session, const std::vector<SlotDelayMargin>& margins) {
  if (session.spec().real_time.force) return;
  for (const SlotDelayMargin& g : margins) {
    if (!g.unstable()) continue;
    throw ConfigError(fmt::format(
        "real time: slot {}: the plant's delay after compensation, {:.3f} ms (plant {:.3f} ms, "
        "compensated {:.3f} ms), exceeds the critical delay {:.3f} ms (at {:.2f} Hz, K0 = {:.6g} "
        "N/m): the test would go unstable. Compensate the delay (transfer: {{type: compensated, "
        "...}}), add damping to the numerical model, or set real_time.force: true to run it "
        "anyway (docs/real-time.md)", g.slot, 1e3 * g.remaining_delay, 1e3 * g.plant_delay,
        1e3 * g.compensation, 1e3 * g.critical_delay, g.crossing_hz, g.k0));
  }
}

nlohmann::json ToJson(const std::vector<SlotDelayMargin>& margins) {
  nlohmann::json out = nlohmann::json::array();
  for (const SlotDelayMargin& g : margins) {
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    out.push_back({{"slot", g.slot}, {"substructure", g.substructure}, {"k0", g.k0}, {"critical_delay_s", num(g.critical_delay)},
                   {"crossing_hz", g.crossing_hz}, {"delayed_together", g.delayed_together}, {"plant_delay_s", g.plant_delay},
                   {"compensation_s", g.compensation}, {"remaining_delay_s", g.remaining_delay},
                   {"unstable", g.unstable()}});
  }
  return out;
}

}  // namespace hybridtest::runner
