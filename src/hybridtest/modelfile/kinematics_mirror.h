#pragma once
// velocity(P, F).x and angular_velocity(A, F).z in model-file loads. The engine's loads see
// t, q, u and r only (multibody::LoadArgs), so the model-file layer keeps its own copy of the
// frames (each a rotation about a fixed axis by an angle expression, as the reader builds
// them) and points, and evaluates the velocity of a point or angular velocity of a frame in N
// from them: each angle and position component on a Jet<S> gives its value and d/dt along
// q̇ = W(q) u, and rotations and positions are composed down the chain. For S = AutoDiff the
// result carries its exact derivatives (the state Jacobian stays exact). No heap allocation.
// Included at the end of expression_eval.h.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross
#include <array>
#include <map>
#include <string>
#include <vector>

#include "hybridtest/modelfile/expression_eval.h"

namespace hybridtest::modelfile {

struct Mirror {
  struct Frame {
    int parent = -1;  // −1 for N (frame 0)
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit, in the parent
    Expression angle = Expression::Constant(0.0);
  };
  struct Point {
    int from = -1;  // −1 for O (point 0)
    int frame = 0;
    std::array<Expression, 3> position{Expression::Constant(0.0), Expression::Constant(0.0),
                                       Expression::Constant(0.0)};
  };
  std::vector<Frame> frames;  // [0] is N
  std::vector<Point> points;  // [0] is O
  std::map<std::string, int> frame_ids, point_ids;
  std::vector<Expression> W;  // n × n, row-major; empty: q̇ = u
  int num_coordinates = 0;
};

namespace mirror_detail {
template <typename S>
struct Motion {
  Eigen::Matrix<S, 3, 3> R;     // N ← frame
  Eigen::Matrix<S, 3, 1> w;     // angular velocity in N, N components
};

// An expression's value and d/dt along the motion (q̇ given), from a Jet<S> without ∂/∂q.
template <typename S>
void ValueAndRate(const Expression& e, const S& t, std::span<const S> q, std::span<const S> qdot,
                  S* value, S* rate) {
  using J = multibody::Jet<S>;
  std::array<J, multibody::kMaxJetCoordinates> jq;
  for (std::size_t k = 0; k < q.size(); ++k) {
    jq[k].v = q[k];
    jq[k].d1 = qdot[k];
  }
  J jt(0.0);
  jt.v = t;
  jt.d1 = S(1.0);
  const J r = Evaluate(e, Variables<J>{jt, std::span<const J>(jq.data(), q.size()), {}, {}, {}});
  *value = r.v;
  *rate = r.d1;
}

template <typename S>
Motion<S> FrameMotion(const Mirror& m, int f, const S& t, std::span<const S> q,
                      std::span<const S> qdot) {
  Motion<S> out;
  if (f <= 0) {
    out.R.setIdentity();
    out.w.setZero();
    return out;
  }
  const Mirror::Frame& fr = m.frames[static_cast<std::size_t>(f)];
  const Motion<S> parent = FrameMotion(m, fr.parent, t, q, qdot);
  S theta, theta_dot;
  ValueAndRate(fr.angle, t, q, qdot, &theta, &theta_dot);
  using std::cos; using std::sin;
  const S c = cos(theta), s = sin(theta);
  const Eigen::Vector3d a = fr.axis;
  Eigen::Matrix<S, 3, 3> rot;
  // Rodrigues: the child's unit vectors in the parent, rotated by θ about a (right-handed).
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) rot(i, k) = S((1.0 - c) * (a(i) * a(k)));
    rot(i, i) = S(rot(i, i) + c);
  }
  rot(0, 1) = S(rot(0, 1) - s * a(2));
  rot(1, 0) = S(rot(1, 0) + s * a(2));
  rot(0, 2) = S(rot(0, 2) + s * a(1));
  rot(2, 0) = S(rot(2, 0) - s * a(1));
  rot(1, 2) = S(rot(1, 2) - s * a(0));
  rot(2, 1) = S(rot(2, 1) + s * a(0));
  out.R = parent.R * rot;
  const Eigen::Matrix<S, 3, 1> axis_n = parent.R * a.cast<S>();
  out.w = parent.w + axis_n * theta_dot;
  return out;
}

// Position and velocity of point p in N (N components).
template <typename S>
void PointMotion(const Mirror& m, int p, const S& t, std::span<const S> q,
                 std::span<const S> qdot, Eigen::Matrix<S, 3, 1>* r, Eigen::Matrix<S, 3, 1>* v) {
  if (p <= 0) {
    r->setZero();
    v->setZero();
    return;
  }
  const Mirror::Point& pt = m.points[static_cast<std::size_t>(p)];
  PointMotion(m, pt.from, t, q, qdot, r, v);
  const Motion<S> frame = FrameMotion(m, pt.frame, t, q, qdot);
  Eigen::Matrix<S, 3, 1> local, local_rate;
  for (int k = 0; k < 3; ++k) {
    ValueAndRate(pt.position[static_cast<std::size_t>(k)], t, q, qdot, &local(k), &local_rate(k));
  }
  const Eigen::Matrix<S, 3, 1> offset = frame.R * local;
  *r += offset;
  *v += frame.w.cross(offset) + frame.R * local_rate;
}
}  // namespace mirror_detail

template <typename S>
S MirrorVelocity(const Mirror& m, bool angular, int id, int frame, int component,
                 const Variables<S>& v) {
  const std::size_t n = v.q.size();
  std::array<S, multibody::kMaxJetCoordinates> qdot;
  for (std::size_t i = 0; i < n; ++i) {
    if (m.W.empty()) {
      qdot[i] = v.u[i];
      continue;
    }
    S sum(0.0);
    const Variables<S> at{v.t, v.q, {}, {}, {}};
    for (std::size_t k = 0; k < n; ++k) sum += Evaluate(m.W[i * n + k], at) * v.u[k];
    qdot[i] = sum;
  }
  const std::span<const S> qd(qdot.data(), n);
  Eigen::Matrix<S, 3, 1> vec;
  if (angular) {
    vec = mirror_detail::FrameMotion(m, id, v.t, v.q, qd).w;
  } else {
    Eigen::Matrix<S, 3, 1> r;
    mirror_detail::PointMotion(m, id, v.t, v.q, qd, &r, &vec);
  }
  const Eigen::Matrix<S, 3, 3> R = mirror_detail::FrameMotion(m, frame, v.t, v.q, qd).R;
  return S(R.col(component).dot(vec));
}

}  // namespace hybridtest::modelfile
