// The rotor's right-hand side written out by hand. See rotor_closed_form.h.
#include "rotor_closed_form.h"

#include <Eigen/Cholesky>

#include <cmath>
#include <numbers>

namespace hybridtest::bench {

namespace {
constexpr int kBlades = 3;
constexpr double kPsi[kBlades] = {0.0, 2.0 * std::numbers::pi / 3.0, 4.0 * std::numbers::pi / 3.0};
}  // namespace

void CalcRotorMassMatrix(const RotorParameters& p, const RotorState& x, Eigen::Matrix4d& M) {
  const double ml = p.m_b * p.l_b;
  M.setZero();
  M(3, 3) = p.I_g;
  for (int i = 0; i < kBlades; ++i) {
    M(i, i) = p.m_b;
    M(i, 3) = ml;
    M(3, i) = ml;
    M(3, 3) += p.m_b * (p.l_b * p.l_b + x(i) * x(i));
  }
}

void CalcRotorForcing(const RotorParameters& p, double t, const RotorState& x,
                      const Eigen::Vector3d& r, Eigen::Vector4d& g) {
  const double rho = 1.0 - std::exp(-t / p.t0);  // the ramp of Eq. (12), once
  const double c = p.zeta_b * p.m_b;
  const double w = x(7);  // θ̇ [rad/s]
  const double w2 = w * w;
  const double mg_rho = p.m_b * p.g * rho;
  const double wind = rho * p.f_w;
  g(3) = -p.d_g * w;
  for (int i = 0; i < kBlades; ++i) {
    const double q = x(i), u = x(4 + i);
    const double phi = x(3) + kPsi[i];
    const double s = std::sin(phi), co = std::cos(phi);
    // Force on the tip along b̂_iy and b̂_ix, minus the remainder inertia force m_b a_rem.
    const double fy = wind - mg_rho * s + p.m_b * w2 * q;
    const double fx = mg_rho * co + p.m_b * (2.0 * u * w + p.l_b * w2);
    g(i) = fy - (r(i) + c * u);
    g(3) += p.l_b * fy - q * fx;
  }
}

void CalcRotorRhs(const RotorParameters& p, double t, const RotorState& x,
                  const Eigen::Vector3d& r, RotorState& xdot) {
  Eigen::Matrix4d M;
  Eigen::Vector4d g;
  CalcRotorMassMatrix(p, x, M);
  CalcRotorForcing(p, t, x, r, g);
  const Eigen::LLT<Eigen::Matrix4d> llt(M);
  xdot.head<4>() = x.tail<4>();
  xdot.tail<4>() = llt.solve(g);
}

void CalcRotorRhsArrow(const RotorParameters& p, double t, const RotorState& x,
                       const Eigen::Vector3d& r, RotorState& xdot) {
  Eigen::Vector4d g;
  CalcRotorForcing(p, t, x, r, g);
  // Schur complement of the blades' diagonal block: s = I_g + Σ m_b q_i².
  const double s = p.I_g + p.m_b * x.head<3>().squaredNorm();
  const double wdot = (g(3) - p.l_b * g.head<3>().sum()) / s;
  xdot.head<4>() = x.tail<4>();
  for (int i = 0; i < kBlades; ++i) xdot(4 + i) = g(i) / p.m_b - p.l_b * wdot;
  xdot(7) = wdot;
}

}  // namespace hybridtest::bench
