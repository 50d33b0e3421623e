#pragma once
// A planar double pendulum of two point masses, exercising chained frames and points located
// from moving points (which the rotor does not).
//
// Frames: A = N turned about n̂_z by q1; B = A turned about â_z by q2 (relative angle).
// Points: P1 = O + l1 â_x (mass m1), P2 = P1 + l2 b̂_x (mass m2). Gravity m_i g n̂_x at P_i
// (n̂_x points down). u = q̇. Conservative: the energy
//   E = ½ m1 |v1|² + ½ m2 |v2|² − g (m1 x1 + m2 x2)
// is constant. No restoring-force slots.
// Parameters: m1, m2 [kg], l1, l2 [m], g [m/s²].
#include "hybridtest/models/catalogue.h"

namespace hybridtest::models {

ParameterSet DoublePendulumDefaultParameters();
BuiltModel BuildDoublePendulum(const ParameterSet& parameters);

}  // namespace hybridtest::models
