#pragma once
// Constraints of a multibody model, as the user writes them (ModelBuilder::Add*Constraint;
// the equations the engine builds from them are in constraints.h).
//
// Every constraint contributes one or more rows to the velocity constraints
//
//   B(q, t) u + c(q, t) = 0                                  (m rows, linear in u)
//
// A holonomic row comes from a configuration constraint f(q, t) = 0 differentiated once
// (B = ∂f/∂q W(q), c = ∂f/∂t); its residual f is kept for assembly, stabilisation and
// linearisation. A nonholonomic row is given at velocity level.
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/multibody/kinematic_field.h"

namespace hybridtest::multibody {

struct ConstraintSpec {
  enum class Kind {
    kHolonomic,     // field(q, t) = 0                                    1 row, holonomic
    kNonholonomic,  // Σ_j coefficient_j(q, t) u_j + constant(q, t) = 0   1 row
    kCoincident,    // components of p_OP − p_OQ in `expressed_in` = 0    holonomic rows
    kVelocity,      // components of the velocity of P in `expressed_in` = 0 (P as a point
                    // of `body` through `body_point`, fixed in it: rolling contact)
  };
  std::string name;  // as the user wrote it: "loop closure", "rear contact"
  Kind kind = Kind::kHolonomic;
  ScalarField field;  // kHolonomic: f(q, t) [m, rad or 1]
  // kNonholonomic: (speed index, coefficient B_j(q, t)) pairs and c(q, t). Unit: the row's
  // unit per unit of u_j, and the row's unit [m/s, rad/s or 1/s].
  std::vector<std::pair<int, ScalarField>> coefficients;
  ScalarField constant;
  int point = -1;         // kCoincident, kVelocity: P
  int other = -1;         // kCoincident: Q
  int body = -1;          // kVelocity: the frame P is a point of (−1: P's own velocity)
  int body_point = -1;    // kVelocity: a point fixed in `body` (with body ≥ 0)
  int expressed_in = 0;   // kCoincident, kVelocity: frame of the components
  std::vector<int> components;  // kCoincident, kVelocity: 0, 1, 2 (x, y, z of expressed_in)
  // Whether a run records this constraint's force, its multipliers λ (one per row,
  // constraints.h CalcConstraintForces), as journal channels, and their unit: [N] for
  // kCoincident and kVelocity rows (the force on P along a component of expressed_in); for an
  // expression, the work unit over the row's unit: [N] for f in m, [N·m] for f in rad
  // (ModelBuilder::RecordConstraintForce).
  bool record_force = false;
  std::string force_unit = "N";

  int num_rows() const {
    return kind == Kind::kHolonomic || kind == Kind::kNonholonomic
               ? 1 : static_cast<int>(components.size());
  }
  bool holonomic() const { return kind == Kind::kHolonomic || kind == Kind::kCoincident; }
};

// How the model treats its constraints (ModelBuilder::SetConstraintOptions).
struct ConstraintOptions {
  // Speeds solved from the constraints (m of them, 0-based), or empty: the engine picks them
  // by a completely pivoted elimination of B at every evaluation (the equations' solution u̇
  // does not depend on the choice; the printed reduced equations do).
  std::vector<int> dependent_speeds;
  // Coordinates solved from the holonomic constraints when a state is assembled (as many as
  // holonomic rows), or empty: picked by pivoting ∂f/∂q.
  std::vector<int> dependent_coordinates;
  // Baumgarte stabilisation time constant τ [s] (α = 1/τ): the acceleration constraints
  // become f̈ + 2α ḟ + α² f = 0 (holonomic rows) and ġ + 2α g = 0 (nonholonomic rows,
  // g = B u + c). 0 switches stabilisation off. On the constraint manifold the terms vanish.
  double stabilisation_time_constant = 0.05;
  // Largest holonomic residual |f| [m or rad] an assembled state may keep; also the
  // tolerance a long run is held to (docs/decisions/0023-constraints.md).
  double tolerance = 1e-10;
};

}  // namespace hybridtest::multibody
