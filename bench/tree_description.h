#pragma once
// One description of a tree of bodies, from which the side-by-side benchmarks build both the
// hybridtest model (ModelBuilder) and the MuJoCo model (MJCF, bench/mujoco/): each body hangs
// from its parent by one joint, a hinge about `axis` through the body's origin or a slide
// along `axis`; the body's origin sits at `offset` from the parent's origin (parent axes),
// its mass centre at `com` (body axes), with principal inertia `inertia` (body axes).
// Gravity acts along −z. Bodies are listed parents first and depth first, so body i's joint
// is q_i in both engines (MuJoCo orders qpos the same way).
#include <Eigen/Core>
#include <fmt/core.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "hybridtest/multibody/model.h"

namespace hybridtest::bench {

struct BodyDescription {
  int parent = -1;  // −1: the world
  bool hinge = true;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // [m]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();     // [m]
  double mass = 1.0;                                 // [kg]
  Eigen::Vector3d inertia = Eigen::Vector3d::Constant(1e-3);  // [kg·m²]
};

inline constexpr double kGravity = 9.81;  // [m/s²], along −z

// An n-link pendulum: hinges about y, links 0.3 m long with their mass at the tip.
inline std::vector<BodyDescription> ChainDescription(int n) {
  std::vector<BodyDescription> bodies;
  for (int i = 0; i < n; ++i) {
    BodyDescription b;
    b.parent = i - 1;
    b.offset = i == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.3, 0.0, 0.0);
    b.com = Eigen::Vector3d(0.3, 0.0, 0.0);
    b.mass = 0.5;
    b.inertia = Eigen::Vector3d(1e-4, 2e-4, 2e-4);
    bodies.push_back(b);
  }
  return bodies;
}

// A tower top that sways (slide along x), a hub that spins about x, and three blades of
// `links` bodies each (flap hinges about each segment's y): n = 2 + 3 links.
inline std::vector<BodyDescription> RotorTreeDescription(int links) {
  std::vector<BodyDescription> bodies;
  BodyDescription tower;
  tower.hinge = false;
  tower.axis = Eigen::Vector3d::UnitX();
  tower.offset = Eigen::Vector3d(0.0, 0.0, 20.0);
  tower.mass = 100.0;
  tower.inertia = Eigen::Vector3d(10.0, 10.0, 5.0);
  bodies.push_back(tower);
  BodyDescription hub;
  hub.parent = 0;
  hub.axis = Eigen::Vector3d::UnitX();
  hub.offset = Eigen::Vector3d(-1.5, 0.0, 0.5);
  hub.mass = 10.0;
  hub.inertia = Eigen::Vector3d(2.0, 1.0, 1.0);
  bodies.push_back(hub);
  for (int blade = 0; blade < 3; ++blade) {
    const double angle = 2.0 * std::numbers::pi * blade / 3.0;
    const Eigen::Vector3d radial(0.0, -std::sin(angle), std::cos(angle));  // in the hub
    for (int k = 0; k < links; ++k) {
      BodyDescription s;
      s.parent = k == 0 ? 1 : static_cast<int>(bodies.size()) - 1;
      // Segments run along the blade's radial direction; flap about the hub's y turned with
      // the blade, approximated here by the axis normal to x and the radial direction.
      s.axis = Eigen::Vector3d::UnitX().cross(radial);
      s.offset = k == 0 ? (0.5 * radial).eval() : (0.8 * radial).eval();
      s.com = 0.4 * radial;
      s.mass = 2.0 - 0.1 * k;
      s.inertia = Eigen::Vector3d(0.05, 0.05, 0.01);
      bodies.push_back(s);
    }
  }
  return bodies;
}

// The hybridtest model of a description: one frame per hinge, one point per body origin and
// mass centre, one rigid body and one gravity force per body.
inline multibody::Model BuildKaneModel(const std::vector<BodyDescription>& bodies) {
  using multibody::ScalarField;
  std::vector<multibody::QuantityInfo> q;
  for (std::size_t i = 0; i < bodies.size(); ++i) q.push_back({fmt::format("q{}", i + 1), "", ""});
  multibody::ModelBuilder b(q);
  std::vector<multibody::FrameId> frame;
  std::vector<multibody::PointId> origin;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyDescription& d = bodies[i];
    const int k = static_cast<int>(i);
    const multibody::FrameId parent_frame = d.parent < 0 ? b.newtonian() : frame[d.parent];
    const multibody::PointId parent_origin = d.parent < 0 ? b.origin() : origin[d.parent];
    std::array<ScalarField, 3> position;
    for (int c = 0; c < 3; ++c) {
      position[c] = d.hinge || d.axis(c) == 0.0
                        ? ScalarField::Constant(d.offset(c))
                        : ScalarField::Affine(d.offset(c), {{k, d.axis(c)}});
    }
    const multibody::PointId o = b.AddPoint("O", parent_origin, parent_frame, position);
    const multibody::FrameId f =
        d.hinge ? b.AddFrameAboutAxis("F", parent_frame, d.axis, ScalarField::Coordinate(k))
                : parent_frame;
    const multibody::PointId g = b.AddPoint(
        "G", o, f, {ScalarField::Constant(d.com(0)), ScalarField::Constant(d.com(1)),
                    ScalarField::Constant(d.com(2))});
    b.AddRigidBody("body", f, g, d.mass, d.inertia.asDiagonal());
    const double weight = d.mass * kGravity;
    b.AddForce("gravity", g, b.newtonian(), [weight](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      return multibody::Vector3<T>(T(0.0), T(0.0), T(-weight));
    });
    frame.push_back(f);
    origin.push_back(o);
  }
  return std::move(b).Build();
}

}  // namespace hybridtest::bench
