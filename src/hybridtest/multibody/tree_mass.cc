// The composite (CRBA-style) mass matrix of a tree of joints. See tree_mass.h and decision 0012.
#include "hybridtest/multibody/tree_mass.h"

#include <fmt/core.h>

#include <algorithm>
#include <iterator>

namespace hybridtest::multibody::internal {
namespace {

bool Has(const std::vector<int>& sorted, int j) {
  return std::binary_search(sorted.begin(), sorted.end(), j);
}

}  // namespace

std::string PlanTreeMassMatrix(const ModelElements& e, const std::vector<CompiledFrame>& frames,
                               const std::vector<CompiledPoint>& points, TreeMassPlan& plan) {
  plan = TreeMassPlan{};
  const int n = static_cast<int>(e.coordinates.size());
  if (e.kinematic_matrix) return "kinematical equations q̇ = W(q) u";
  // Where each coordinate appears: frame angles (revolute) and point positions (prismatic).
  std::vector<std::vector<int>> in_frames(static_cast<std::size_t>(n));
  std::vector<std::vector<int>> in_points(static_cast<std::size_t>(n));
  for (std::size_t i = 1; i < e.frames.size(); ++i) {
    const FrameSpec& f = e.frames[i];
    if (f.kind != FrameSpec::Kind::kAxisAngle || !f.angle.is_affine()) {
      return fmt::format("frame '{}' is not an affine rotation about a fixed axis", f.name);
    }
    for (const auto& term : f.angle.terms()) in_frames[term.coordinate].push_back(int(i));
  }
  for (std::size_t i = 1; i < e.points.size(); ++i) {
    const PointSpec& p = e.points[i];
    for (const auto& c : p.position) {
      if (!c.is_affine()) return fmt::format("point '{}' has a general position expression", p.name);
      for (const auto& term : c.terms()) {
        auto& list = in_points[term.coordinate];
        if (list.empty() || list.back() != int(i)) list.push_back(int(i));
      }
    }
  }
  plan.joints.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const std::size_t places = in_frames[j].size() + in_points[j].size();
    if (places != 1) {
      return fmt::format("coordinate '{}' appears in {} frame angles and {} point positions; a "
                         "joint appears in exactly one", e.coordinates[j].name,
                         in_frames[j].size(), in_points[j].size());
    }
    TreeMassPlan::Joint& joint = plan.joints[j];
    if (!in_points[j].empty()) {
      joint.point = in_points[j][0];  // prismatic: ω_j = 0, v_j the same for all it moves
      continue;
    }
    joint.frame = in_frames[j][0];
    // Revolute: every point it moves is moved rigidly about one pivot point it does not move.
    auto set_pivot = [&](int candidate, const std::string& what) -> std::string {
      if (joint.pivot < 0 || joint.pivot == candidate) {
        joint.pivot = candidate;
        return "";
      }
      return fmt::format("coordinate '{}' turns {} about point '{}' and others about '{}'",
                         e.coordinates[j].name, what, e.points[candidate].name,
                         e.points[joint.pivot].name);
    };
    for (std::size_t i = 1; i < e.points.size(); ++i) {
      const PointSpec& p = e.points[i];
      const bool by_from = Has(points[p.from].active, j);
      const bool by_frame = Has(frames[p.frame].active, j);
      if (by_from && !by_frame) {
        return fmt::format("point '{}' moves with '{}' through point '{}' but is placed in a "
                           "frame that does not turn with it", p.name, e.coordinates[j].name,
                           e.points[p.from].name);
      }
      if (by_frame && !by_from) {
        if (auto why = set_pivot(p.from, "point '" + p.name + "'"); !why.empty()) return why;
      }
    }
    for (const RigidBodySpec& b : e.bodies) {
      if (!(b.mass > 0.0)) continue;
      const bool by_frame = Has(frames[b.frame].active, j);
      const bool by_centre = Has(points[b.mass_center].active, j);
      if (by_centre && !by_frame) {
        return fmt::format("rigid body '{}': its mass centre moves with '{}' but its frame does "
                           "not turn with it", b.name, e.coordinates[j].name);
      }
      if (by_frame && !by_centre) {
        if (auto why = set_pivot(b.mass_center, "body '" + b.name + "'"); !why.empty()) return why;
      }
    }
  }
  // Mass elements and, per speed, the sorted elements it moves.
  std::vector<std::vector<int>> moves(static_cast<std::size_t>(n));
  std::vector<std::vector<int>> element_active;
  auto add_element = [&](TreeMassPlan::Element el) {
    std::vector<int> active;
    if (el.mass > 0.0) active = points[el.point].active;
    if (el.has_inertia) {
      const auto& fa = frames[el.frame].active;
      std::vector<int> u;
      std::set_union(active.begin(), active.end(), fa.begin(), fa.end(), std::back_inserter(u));
      active = std::move(u);
    }
    const int index = static_cast<int>(plan.elements.size());
    for (int j : active) moves[j].push_back(index);
    plan.elements.push_back(el);
    element_active.push_back(std::move(active));
  };
  for (const ParticleSpec& p : e.particles) add_element({p.point, -1, p.mass, Eigen::Matrix3d::Zero(), false});
  for (const RigidBodySpec& b : e.bodies) {
    const bool inertia = !b.inertia.isZero(0.0);
    if (b.mass > 0.0 || inertia) add_element({b.mass_center, b.frame, b.mass, b.inertia, inertia});
  }
  // Structurally non-zero pairs; the sets moved by each pair must be nested (a tree).
  std::vector<char> seen(static_cast<std::size_t>(n) * n, 0);
  for (const auto& active : element_active) {
    for (std::size_t a = 0; a < active.size(); ++a) {
      for (std::size_t b = a; b < active.size(); ++b) {
        const int j = active[a];
        const int k = active[b];
        char& s = seen[static_cast<std::size_t>(j) * n + k];
        if (s) continue;
        s = 1;
        const auto& mj = moves[j];
        const auto& mk = moves[k];
        int outer, inner;
        if (std::includes(mj.begin(), mj.end(), mk.begin(), mk.end())) {
          outer = j;
          inner = k;
        } else if (std::includes(mk.begin(), mk.end(), mj.begin(), mj.end())) {
          outer = k;
          inner = j;
        } else {
          return fmt::format("coordinates '{}' and '{}' move overlapping but not nested sets of "
                             "masses (not a tree of joints)", e.coordinates[j].name,
                             e.coordinates[k].name);
        }
        plan.pairs.push_back({outer, inner, j + k * n, k + j * n});
      }
    }
  }
  // The joint tree: inner before outer by (size of the moved set, then −index), so joints
  // that move the same set form a chain.
  auto inner_first = [&](int a, int b) {
    return moves[a].size() != moves[b].size() ? moves[a].size() < moves[b].size() : a > b;
  };
  plan.owner.assign(plan.elements.size(), -1);
  for (std::size_t el = 0; el < plan.elements.size(); ++el) {
    for (int k : element_active[el]) {
      if (plan.owner[el] < 0 || inner_first(k, plan.owner[el])) plan.owner[el] = k;
    }
  }
  plan.parent.assign(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < n; ++k) {
    if (moves[k].empty()) continue;
    plan.order.push_back(k);
    for (int j = 0; j < n; ++j) {
      if (j == k || !inner_first(k, j)) continue;
      if (!std::includes(moves[j].begin(), moves[j].end(), moves[k].begin(), moves[k].end())) continue;
      if (plan.parent[k] < 0 || inner_first(j, plan.parent[k])) plan.parent[k] = j;
    }
  }
  std::sort(plan.order.begin(), plan.order.end(), inner_first);
  return "";
}

template <typename T>
void CalcTreeMassMatrix(const Model& model, Data<T>& data) {
  const TreeMassPlan& plan = model.tree_mass_plan();
  const int n = data.n;
  Matrix3X<T>& Sw = data.joint_w;
  Matrix3X<T>& Sv = data.joint_v;
  Matrix3X<T>& Hv = data.momentum_lin;
  Matrix3X<T>& Hw = data.momentum_ang;
  // Joint axes S_j = (ω_j, v_j(O)) in N.
  for (int j = 0; j < n; ++j) {
    const TreeMassPlan::Joint& joint = plan.joints[j];
    if (joint.frame >= 0) {
      Sw.col(j) = data.w_partial[joint.frame].col(j);
      if (joint.pivot >= 0) {
        Sv.col(j) = data.p_OP[joint.pivot].cross(Vector3<T>(Sw.col(j)));
      } else {
        Sv.col(j).setZero();
      }
    } else {
      Sw.col(j).setZero();
      Sv.col(j) = data.v_partial[joint.point].col(j);
    }
  }
  // Composite inertias about O: each element into its joint, then children into parents.
  VectorX<T>& cm = data.composite_mass;
  Matrix3X<T>& cc = data.composite_moment;
  std::vector<Matrix3<T>>& ci = data.composite_inertia;
  for (int k : plan.order) {
    cm(k) = T(0.0);
    cc.col(k).setZero();
    ci[k].setZero();
  }
  for (std::size_t e = 0; e < plan.elements.size(); ++e) {
    const int k = plan.owner[e];
    if (k < 0) continue;
    const TreeMassPlan::Element& el = plan.elements[e];
    if (el.mass > 0.0) {
      const Vector3<T>& p = data.p_OP[el.point];
      const Vector3<T> c = el.mass * p;
      cm(k) += el.mass;
      cc.col(k) += c;
      // m (|p|² 1 − p pᵀ)
      Matrix3<T>& I = ci[k];
      const T pp = p.squaredNorm();
      I.noalias() -= c * p.transpose();
      for (int a = 0; a < 3; ++a) I(a, a) += el.mass * pp;
    }
    if (el.has_inertia) {
      const Matrix3<T>& R = data.R_NF[el.frame];
      ci[k].noalias() += R * el.inertia.template cast<T>() * R.transpose();
    }
  }
  for (int k : plan.order) {
    const int parent = plan.parent[k];
    if (parent < 0) continue;
    cm(parent) += cm(k);
    cc.col(parent) += cc.col(k);
    ci[parent] += ci[k];
  }
  // Spatial momentum about O per unit u_k: (m v_O + ω × c, c × v_O + I_O ω).
  Hv.setZero();
  Hw.setZero();
  for (int k : plan.order) {
    const Vector3<T> w = Sw.col(k);
    const Vector3<T> v = Sv.col(k);
    const Vector3<T> c = cc.col(k);
    Hv.col(k) = cm(k) * v + w.cross(c);
    Hw.col(k) = c.cross(v) + ci[k] * w;
  }
  // M_jk = S_outer · H_inner.
  T* m = data.M.data();
  data.M.setZero();
  for (const TreeMassPlan::Pair& pair : plan.pairs) {
    const T value =
        Sw.col(pair.outer).dot(Hw.col(pair.inner)) + Sv.col(pair.outer).dot(Hv.col(pair.inner));
    m[pair.m_jk] = value;
    m[pair.m_kj] = value;
  }
}

template void CalcTreeMassMatrix<double>(const Model&, Data<double>&);
template void CalcTreeMassMatrix<AutoDiff>(const Model&, Data<AutoDiff>&);

}  // namespace hybridtest::multibody::internal
