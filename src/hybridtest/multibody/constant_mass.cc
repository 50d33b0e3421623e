// The constant entries of a planar model's mass matrix. See constant_mass.h.
#include "hybridtest/multibody/constant_mass.h"

#include <array>
#include <cmath>

#include "hybridtest/multibody/compile.h"

namespace hybridtest::multibody::internal {
namespace {

// One component of a segment's vector a: a constant, or something that varies with q or t.
struct Component {
  double value = 0.0;
  bool varying = false;
  bool zero() const { return !varying && value == 0.0; }
};

struct Segment {
  int frame = 0;
  std::array<Component, 3> a;
};

// What a frame's angle θ_E = θ0 + Σ w_k q_k + c_t t says about relative rotations.
struct FrameAngle {
  std::vector<double> w;  // (n) constant partial angular velocities about e_A
  double time_rate = 0.0;
  double theta0 = 0.0;
};

}  // namespace

ConstantMassPlan CompileConstantMass(const ModelElements& e,
                                     const std::vector<CompiledFrame>& frames,
                                     const std::vector<CompiledPoint>& points, int A,
                                     const std::vector<char>& nz) {
  ConstantMassPlan plan;
  const int n = static_cast<int>(e.coordinates.size());
  if (A < 0 || n > 6 || e.kinematic_matrix) return plan;
  const int B = (A + 1) % 3, D = (A + 2) % 3;
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  std::vector<FrameAngle> angle(e.frames.size(), FrameAngle{std::vector<double>(n, 0.0)});
  for (std::size_t i = 1; i < e.frames.size(); ++i) {
    const FrameSpec& spec = e.frames[i];
    if (spec.kind != FrameSpec::Kind::kAxisAngle || frames[i].axis_index != A ||
        !spec.angle.is_affine() || !(frames[i].axis(A) > 0.0)) {
      return plan;
    }
    angle[i] = angle[static_cast<std::size_t>(spec.parent)];
    for (const auto& term : spec.angle.terms()) angle[i].w[term.coordinate] += term.coefficient;
    angle[i].time_rate += spec.angle.time_rate();
    angle[i].theta0 += spec.angle.constant();
  }
  // Segments of every point's partial velocities, per speed.
  std::vector<std::vector<std::vector<Segment>>> segments(
      e.points.size(), std::vector<std::vector<Segment>>(static_cast<std::size_t>(n)));
  for (std::size_t i = 1; i < e.points.size(); ++i) {
    const PointSpec& spec = e.points[i];
    const CompiledPoint& pt = points[i];
    if (!pt.affine) return plan;
    std::array<Component, 3> r;
    for (int c = 0; c < 3; ++c) {
      r[c] = {pt.offset(c), pt.has_time_rate && pt.time_rate(c) != 0.0};
    }
    for (const auto& term : pt.rate_terms) r[term.component].varying = true;
    std::array<Component, 3> cross;  // e_A × r
    cross[A] = {0.0, false};
    cross[B] = {-r[D].value, r[D].varying};
    cross[D] = {r[B].value, r[B].varying};
    const FrameAngle& frame = angle[static_cast<std::size_t>(spec.frame)];
    for (int j : pt.active) {
      std::vector<Segment>& mine = segments[i][j];
      mine = segments[static_cast<std::size_t>(spec.from)][j];
      Segment own{spec.frame, {}};
      const double w = frame.w[j];
      for (int c = 0; c < 3; ++c) {
        if (w != 0.0) own.a[c] = {w * cross[c].value, cross[c].varying};
      }
      for (const auto& term : pt.rate_terms) {
        if (term.speed == j) own.a[term.component].value += term.coefficient;
      }
      if (!own.a[0].zero() || !own.a[1].zero() || !own.a[2].zero()) mine.push_back(own);
    }
  }
  plan.entry.assign(nn, 0);
  plan.value.assign(nn, 0.0);
  struct Element {
    int point;
    double mass;
  };
  std::vector<Element> elements;
  for (const auto& pa : e.particles) elements.push_back({pa.point, pa.mass});
  for (const auto& b : e.bodies) {
    if (b.mass > 0.0) elements.push_back({b.mass_center, b.mass});
  }
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j <= k; ++j) {
      bool constant = true;
      double value = 0.0;
      for (const Element& el : elements) {
        const auto& sj = segments[static_cast<std::size_t>(el.point)][j];
        const auto& sk = segments[static_cast<std::size_t>(el.point)][k];
        for (const Segment& s1 : sj) {
          for (const Segment& s2 : sk) {
            const FrameAngle& f1 = angle[static_cast<std::size_t>(s1.frame)];
            const FrameAngle& f2 = angle[static_cast<std::size_t>(s2.frame)];
            // a1 · R(θ2 − θ1) a2, R about e_A.
            double c = 1.0, s = 0.0;
            if (s1.frame != s2.frame) {
              if (f1.w != f2.w || f1.time_rate != f2.time_rate) {
                constant = false;
                continue;
              }
              c = std::cos(f2.theta0 - f1.theta0);
              s = std::sin(f2.theta0 - f1.theta0);
            }
            const std::array<std::array<double, 3>, 5> terms{
                {{double(A), double(A), 1.0}, {double(B), double(B), c}, {double(D), double(D), c},
                 {double(B), double(D), -s}, {double(D), double(B), s}}};
            for (const auto& t : terms) {
              const Component& x = s1.a[static_cast<std::size_t>(t[0])];
              const Component& y = s2.a[static_cast<std::size_t>(t[1])];
              if (t[2] == 0.0 || x.zero() || y.zero()) continue;
              if (x.varying || y.varying) {
                constant = false;
              } else {
                value += el.mass * (x.value * t[2] * y.value);
              }
            }
          }
        }
      }
      if (!constant) continue;
      for (const auto& b : e.bodies) {
        const auto& w = angle[static_cast<std::size_t>(b.frame)].w;
        value += b.inertia(A, A) * w[j] * w[k];
      }
      for (std::size_t idx : {j + static_cast<std::size_t>(k) * n, k + static_cast<std::size_t>(j) * n}) {
        plan.entry[idx] = 1;
        plan.value[idx] = value;
      }
    }
  }
  // Columns of L that follow from constant entries alone, in CholeskyFactorFixed's order.
  plan.factor_column.assign(static_cast<std::size_t>(n), 0);
  plan.factor.assign(nn, 0.0);
  plan.factor_inv_diag.assign(static_cast<std::size_t>(n), 0.0);
  auto L = [&](int i, int k) -> double& { return plan.factor[static_cast<std::size_t>(i * n + k)]; };
  auto NZ = [&](int i, int k) { return nz[static_cast<std::size_t>(i + k * n)] != 0; };
  for (int j = 0; j < n; ++j) {
    bool constant = plan.entry[static_cast<std::size_t>(j + j * n)] != 0;
    for (int i = j + 1; i < n; ++i) {
      if (NZ(i, j) && !plan.entry[static_cast<std::size_t>(i + j * n)]) constant = false;
    }
    for (int k = 0; k < j; ++k) {
      if (NZ(j, k) && !plan.factor_column[static_cast<std::size_t>(k)]) constant = false;
    }
    if (!constant) continue;
    double d = plan.value[static_cast<std::size_t>(j + j * n)];
    for (int k = 0; k < j; ++k)
      if (NZ(j, k)) d = d - L(j, k) * L(j, k);
    if (!(d > 0.0)) continue;
    const double inv = 1.0 / std::sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      if (!NZ(i, j)) continue;
      double s = plan.value[static_cast<std::size_t>(i + j * n)];
      for (int k = 0; k < j; ++k)
        if (NZ(i, k) && NZ(j, k)) s = s - L(i, k) * L(j, k);
      L(i, j) = s * inv;
    }
    plan.factor_inv_diag[static_cast<std::size_t>(j)] = inv;
    plan.factor_column[static_cast<std::size_t>(j)] = 1;
  }
  return plan;
}

}  // namespace hybridtest::multibody::internal
