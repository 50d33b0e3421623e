#pragma once
// A 3D rigid body with a full inertia dyadic, pivoting about a fixed point O under gravity:
// exercises 3D rotations, products of inertia, gyroscopic terms ω × Iω and non-trivial
// kinematical differential equations (which the rotor does not).
//
// Frames (body-fixed x-y-z sequence): A = N about n̂_x by q1, Bp = A about â_y by q2,
// C = Bp about b̂_z by q3. Generalized speeds are the body-frame components of the angular
// velocity, u_i = ω^C · ĉ_i, so q̇ = W(q) u with
//       ⎡  c3/c2     −s3/c2    0 ⎤
//   W = ⎢  s3         c3       0 ⎥      (c_i = cos q_i, s_i = sin q_i; singular at c2 = 0)
//       ⎣ −s2 c3/c2   s2 s3/c2 1 ⎦
// Mass centre G = O + cx ĉ_x + cy ĉ_y + cz ĉ_z; gravity −m g n̂_z at G. Conservative:
// E = ½ m |v_G|² + ½ ω·I_G ω + m g z_G is constant. No restoring-force slots.
// Parameters: m [kg]; cx, cy, cz [m]; the inertia matrix entries about G in C, Ixx, Iyy, Izz,
// Ixy, Ixz, Iyz [kg·m²]; g [m/s²].
#include "hybridtest/models/catalogue.h"

namespace hybridtest::models {

// q̇ = W(q) u for body-fixed x-y-z angles and body-frame angular velocity components (the W
// above), as a kinematical-matrix function for ModelBuilder::SetKinematicalEquations.
struct BodyXyzKinematics {
  template <class Args, class Span>
  void operator()(const Args& a, Span W) const {
    const auto s2 = sin(a.q[1]), c2 = cos(a.q[1]);
    const auto s3 = sin(a.q[2]), c3 = cos(a.q[2]);
    W[0] = c3 / c2;       W[1] = -s3 / c2;      W[2] = 0.0;
    W[3] = s3;            W[4] = c3;            W[5] = 0.0;
    W[6] = -s2 * c3 / c2; W[7] = s2 * s3 / c2;  W[8] = 1.0;
  }
};

ParameterSet SpinningTopDefaultParameters();
BuiltModel BuildSpinningTop(const ParameterSet& parameters);

}  // namespace hybridtest::models
