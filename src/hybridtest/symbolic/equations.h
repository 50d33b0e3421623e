#pragma once
// Kane's equations of a Model as expressions, from the engine itself (decision 0019).
//
// DeriveEquations runs the numeric engine's CalcKinematics, CalcMassMatrixPairwise and
// CalcForcing on the Symbolic scalar, with a symbol for time t, for every coordinate q_k,
// speed u_k, restoring-force slot r_s and extra state z_k (named as the model names them),
// and simplifies the results (simplify.h). With v_j = ∂v/∂u_j, ω_j = ∂ω/∂u_j:
//
//   Fr_j  = Σ_points v_j·F + Σ_frames ω_j·T                     (applied loads, Kane's Fr)
//   Fr*_j = −Σ_k M_jk u̇_k + (f_j − Fr_j)                       (Kane's Fr*, the paper's Eq. 15)
//   Fr + Fr* = 0   ⇔   M(q, t) u̇ = f(q, u, t, r)                (the paper's Eq. 16)
//
// M and f are exactly the engine's data.M and data.g (SymPy's convention). Model parameters
// enter as their numeric values: the Model stores masses, inertias and affine coefficients as
// doubles (decision 0019, "Parameters").
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/constrained.h"
#include "hybridtest/symbolic/shared.h"

namespace hybridtest::symbolic {

// The partial velocities (or partial angular velocities) of one point (frame): for each speed
// u_j, ∂v/∂u_j in N components. Points and frames whose partials are all zero are left out.
struct NamedPartials {
  std::string name;
  std::vector<std::vector<GiNaC::ex>> columns;  // (n) columns of 3 N components
};

struct Equations {
  GiNaC::ex t;                  // time [s]
  std::vector<GiNaC::ex> q;     // (n) coordinates
  std::vector<GiNaC::ex> u;     // (n) speeds
  std::vector<GiNaC::ex> udot;  // (n) speed rates u̇ (named "<u>_dot")
  std::vector<GiNaC::ex> r;     // (num_slots) static restoring forces
  std::vector<GiNaC::ex> z;     // (nz) extra first-order states
  std::vector<GiNaC::ex> qdot;  // (n) q̇ = W(q) u
  std::vector<GiNaC::ex> zdot;  // (nz) ż = f_z(t, q, u, z)
  std::vector<NamedPartials> point_partials;
  std::vector<NamedPartials> frame_partials;
  std::vector<GiNaC::ex> Fr;       // (n) generalized active forces
  std::vector<GiNaC::ex> Fr_star;  // (n) generalized inertia forces (contain udot)
  std::vector<std::vector<GiNaC::ex>> M;  // (n × n) mass matrix, M u̇ = f
  std::vector<GiNaC::ex> f;               // (n) forcing
  // Empty when the equations are expanded and simplified (simplify.h). Equations whose
  // expansion would exceed kExpandLimit terms (shared.h) keep the engine's expressions instead,
  // written in terms of these named common subexpressions (cse1, cse2, …; the printers print
  // them first). Model parameters then stay numbers.
  SharedSubexpressions shared;
  // A constrained model's dependent speeds, constraint rows and reduced equations
  // (constrained.h); empty (no dependent speeds) for a model without constraints. M and f
  // above are then the tree's, before the constraints.
  ConstrainedEquations constrained;
};

// Every expression of eq, in a fixed order: M by rows, f, Fr, Fr*, q̇, ż, the point partials,
// the frame partials, then a constrained model's (ConstrainedOutputs).
std::vector<GiNaC::ex*> Outputs(Equations& eq);

// Throws ModelError (e.g. a model-file expression that branches on a value, such as `if`).
// A constrained model gets its reduced equations too (constrained.h). `like`, if not null, is
// a derivation of the same model (other parameter values, parameters.h): its symbols (t, q, u,
// u̇, r, z and a constrained model's A) are used instead of new ones, so that the two
// derivations' terms compare equal (GiNaC tells symbols apart by identity, not by name).
Equations DeriveEquations(const multibody::Model& model, const Equations* like = nullptr);

// The engine's M, g, q̇ and ż as the engine computes them, not simplified (code generation,
// codegen.h): the same floats in the same expressions, so that compiled code reproduces the
// numeric engine to rounding.
struct RhsExpressions {
  GiNaC::ex t;                // time [s]
  std::vector<GiNaC::ex> x;   // (2n + nz) the state symbols [q; u; z]
  std::vector<GiNaC::ex> r;   // (num_slots) restoring forces
  std::vector<GiNaC::ex> M;   // (n × n) column-major
  std::vector<GiNaC::ex> g;   // (n)
  std::vector<GiNaC::ex> qdot;  // (n)
  std::vector<GiNaC::ex> zdot;  // (nz)
  // A constrained model's rows of B u + c = 0 (m = num_constraint_rows(); empty without
  // constraints), as CalcConstraints computes them: B (m × n, column-major), B u + c,
  // f(q, t) (0 for non-holonomic rows) and the bias Ḃ u + ċ (m each). The reduction (the
  // dependent speeds, A, [Cᵀ M; B]) stays the engine's numeric code (constraints.h).
  std::vector<GiNaC::ex> B;
  std::vector<GiNaC::ex> constraint_velocity;
  std::vector<GiNaC::ex> constraint_position;
  std::vector<GiNaC::ex> constraint_bias;
};
RhsExpressions DeriveRhs(const multibody::Model& model);

}  // namespace hybridtest::symbolic
