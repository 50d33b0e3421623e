// Build()'s derivations. See compile.h.
#include "hybridtest/multibody/compile.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>

namespace hybridtest::multibody::internal {
namespace {

std::vector<int> Union(const std::vector<int>& a, const std::vector<int>& b) {
  std::set<int> s(a.begin(), a.end());
  s.insert(b.begin(), b.end());
  return {s.begin(), s.end()};
}

// Elements of the sorted `a` that are not in the sorted `b`.
std::vector<int> Difference(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> d;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
  return d;
}

// Speeds whose partial rate of `field` may be non-zero.
std::vector<int> FieldActive(const ModelElements& e, const ScalarField& field) {
  const int n = static_cast<int>(e.coordinates.size());
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) all[j] = j;
  if (!field.is_affine() || e.kinematic_matrix) {
    return field.is_constant() ? std::vector<int>{} : all;
  }
  std::vector<int> active;
  for (const auto& t : field.terms()) active.push_back(t.coordinate);
  return Union(active, {});
}

}  // namespace

CompiledKinematics CompileKinematics(const ModelElements& e) {
  CompiledKinematics out;
  out.frames.resize(e.frames.size());
  out.points.resize(e.points.size());
  out.general = static_cast<bool>(e.kinematic_matrix);
  const bool identity_kinematics = !e.kinematic_matrix;
  for (std::size_t i = 1; i < e.frames.size(); ++i) {
    const FrameSpec& spec = e.frames[i];
    CompiledFrame& f = out.frames[i];
    std::vector<int> own;
    if (spec.kind == FrameSpec::Kind::kAxisAngle) {
      own = FieldActive(e, spec.angle);
      out.general = out.general || !spec.angle.is_affine();
      f.axis = spec.axis / spec.axis.norm();
      for (int a = 0; a < 3; ++a) {
        if (f.axis == Eigen::Vector3d::Unit(a)) f.axis_index = a;
      }
      if (spec.angle.is_constant()) {
        f.constant_rotation = true;
        f.constant_R_PF = Eigen::AngleAxisd(spec.angle.constant(), f.axis).toRotationMatrix();
        f.constant_cos = std::cos(spec.angle.constant());
        f.constant_sin = std::sin(spec.angle.constant());
      }
    } else {
      out.general = true;
      for (int j = 0; j < static_cast<int>(e.coordinates.size()); ++j) own.push_back(j);
    }
    const std::vector<int>& parent_active = out.frames[spec.parent].active;
    f.active = Union(parent_active, own);
    f.fresh = Difference(f.active, parent_active);
    f.affine_angle = spec.kind == FrameSpec::Kind::kAxisAngle && spec.angle.is_affine() &&
                     identity_kinematics;
  }
  for (std::size_t i = 1; i < e.points.size(); ++i) {
    const PointSpec& spec = e.points[i];
    CompiledPoint& p = out.points[i];
    const std::vector<int>& from = out.points[spec.from].active;
    const std::vector<int>& frame = out.frames[spec.frame].active;
    std::vector<int> active = Union(from, frame);
    for (const auto& c : spec.position) {
      active = Union(active, FieldActive(e, c));
      out.general = out.general || !c.is_affine();
    }
    p.active = std::move(active);
    p.affine = identity_kinematics &&
               std::all_of(spec.position.begin(), spec.position.end(),
                           [](const ScalarField& c) { return c.is_affine(); });
    p.from_only = Difference(from, frame);
    p.frame_only = Difference(frame, from);
    p.from_and_frame = Difference(from, p.from_only);
    p.fresh = Difference(Difference(p.active, from), frame);
    if (p.affine) {
      for (int c = 0; c < 3; ++c) {
        p.offset(c) = spec.position[c].constant();
        p.time_rate(c) = spec.position[c].time_rate();
        for (const auto& term : spec.position[c].terms())
          p.rate_terms.push_back({c, term.coordinate, term.coefficient});
      }
      p.has_time_rate = !p.time_rate.isZero(0.0);
    }
  }
  // Planar: every frame turns about the same coordinate axis of its parent (so of N), by an
  // affine or constant angle, and every point is affine, with q̇ = u.
  if (!out.general) {
    int axis = e.frames.size() > 1 ? out.frames[1].axis_index : 2;
    for (std::size_t i = 1; i < e.frames.size(); ++i) {
      const CompiledFrame& f = out.frames[i];
      if (!(f.constant_rotation || f.affine_angle) || f.axis_index != axis) axis = -1;
    }
    for (std::size_t i = 1; i < e.points.size(); ++i) {
      if (!out.points[i].affine) axis = -1;
    }
    out.planar_axis = axis;
  }
  return out;
}

std::vector<MassTerm> CompileMassTerms(const ModelElements& e,
                                       const std::vector<CompiledPoint>& points) {
  const int n = static_cast<int>(e.coordinates.size());
  std::vector<MassTerm> terms;
  auto add = [&](int point, double mass) {
    const std::vector<int>& active = points[point].active;
    for (std::size_t a = 0; a < active.size(); ++a)
      for (std::size_t b = a; b < active.size(); ++b)
        terms.push_back({point, active[a], active[b], mass, 3 * active[a], 3 * active[b],
                         active[a] + active[b] * n, active[b] + active[a] * n});
  };
  for (const auto& pa : e.particles) add(pa.point, pa.mass);
  for (const auto& b : e.bodies) {
    if (b.mass > 0.0) add(b.mass_center, b.mass);
  }
  return terms;
}

namespace {
// Fills in the structure of L in place: column j of L fills row i wherever rows i and j share
// a non-zero left of j.
void FillIn(std::vector<char>& nz, std::size_t n) {
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = j + 1; i < n; ++i)
      for (std::size_t k = 0; k < j && !nz[i + j * n]; ++k)
        if (nz[i + k * n] && nz[j + k * n]) nz[i + j * n] = 1;
}
}  // namespace

std::vector<char> CompileMassStructure(const ModelElements& e,
                                       const std::vector<CompiledFrame>& frames,
                                       const std::vector<MassTerm>& mass_terms,
                                       const TreeMassPlan& plan) {
  const std::size_t n = e.coordinates.size();
  std::vector<char> nz(n * n, 0);
  auto mark = [&](std::size_t j, std::size_t k) { nz[std::max(j, k) + std::min(j, k) * n] = 1; };
  for (std::size_t j = 0; j < n; ++j) mark(j, j);
  for (const MassTerm& t : mass_terms) mark(t.j, t.k);
  for (const RigidBodySpec& b : e.bodies) {
    const std::vector<int>& active = frames[b.frame].active;
    for (int j : active)
      for (int k : active) mark(j, k);
  }
  for (const TreeMassPlan::Pair& p : plan.pairs) mark(p.outer, p.inner);
  return nz;
}

std::vector<char> CompileFactorPattern(std::vector<char> structure, int n) {
  FillIn(structure, static_cast<std::size_t>(n));
  return structure;
}

SparseFactorPlan CompileSparseFactor(const std::vector<char>& structure, int n_int) {
  const std::size_t n = static_cast<std::size_t>(n_int);
  if (n_int <= 6) return {};
  const std::vector<char> pattern = CompileFactorPattern(structure, n_int);
  // The reversed order's structure: M's non-zeros permuted, then its own fill-in.
  std::vector<char> reversed(n * n, 0);
  for (std::size_t j = 0; j < n; ++j) reversed[j + j * n] = 1;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = j + 1; i < n; ++i) {
      if (!structure[i + j * n]) continue;
      const std::size_t a = n - 1 - i, b = n - 1 - j;  // a < b
      reversed[b + a * n] = 1;
    }
  FillIn(reversed, n);
  auto count = [&](const std::vector<char>& nz) {
    std::size_t c = 0;
    for (char x : nz) c += x != 0;
    return c;
  };
  const std::size_t natural_count = count(pattern), reversed_count = count(reversed);
  SparseFactorPlan plan;
  plan.reversed = reversed_count < natural_count;
  const std::vector<char>& nz = plan.reversed ? reversed : pattern;
  if (2 * std::min(natural_count, reversed_count) > n * (n + 1) / 2) return {};
  plan.row_start.push_back(0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < i; ++k)
      if (nz[i + k * n]) plan.columns.push_back(static_cast<int>(k));
    plan.row_start.push_back(static_cast<int>(plan.columns.size()));
  }
  return plan;
}

}  // namespace hybridtest::multibody::internal
