#pragma once
// The reduced equations of a constrained model as expressions (issue 47 item 2), from the
// engine's own constraint rows (multibody/constraints.h: CalcConstraints on the Symbolic
// scalar) and the tree's M and f.
//
// The m velocity constraints B u + c = 0, split by the dependent speeds u_d into
//
//   A_d u_d + A_i u_i + b = 0       (A_d = B's columns of u_d, A_i of u_i, b = c),
//
// and their time derivative B u̇ + (Ḃ u + ċ) = 0. With A = −A_d⁻¹ A_i (m × p) and C the n × p
// matrix whose rows are I (independent speeds) and A (dependent speeds), the reduced equations
// are the engine's (`eom --assemble`, CalcReducedEquations unstabilised):
//
//   [ Cᵀ M ] u̇ = [ Cᵀ f         ]      rows: the p independent speeds, then the m constraints
//   [ B    ]      [ −(Ḃ u + ċ)  ]
//
// A is not inverted symbolically (a 5 × 5 A_d of the bicycle's trigonometry would be huge):
// its entries are the symbols A_s_c (A[s, c], s a dependent speed's row, c an independent
// speed's column), defined by A_d A = −A_i, which a user evaluates at a state by solving that
// system numerically, as the engine does. Everything else is explicit in q, u, t, r, z.
//
// The dependent speeds are the model's (`dependent_speeds:`), else the ones the engine's
// complete pivoting picks at the model's initial state (ChooseDependentSpeeds); the engine
// may pick others at other states, where u̇ is the same (constraints.h).
#include <ginac/ginac.h>

#include <set>
#include <string>
#include <vector>

#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/symbolic.h"

namespace hybridtest::symbolic {

struct ConstrainedEquations {
  std::vector<int> dependent;    // (m) indices of the dependent speeds, ascending
  std::vector<int> independent;  // (p = n − m) the others, ascending
  std::vector<std::string> rows;             // (m) row names: "rear rolling (x)"
  std::vector<std::vector<GiNaC::ex>> A_d;   // (m × m) constraint rows, dependent speeds
  std::vector<std::vector<GiNaC::ex>> A_i;   // (m × p) constraint rows, independent speeds
  std::vector<GiNaC::ex> b;                  // (m) A_d u_d + A_i u_i + b = 0
  std::vector<GiNaC::ex> bias;               // (m) Ḃ u + ċ
  std::vector<std::vector<GiNaC::ex>> A;     // (m × p) the symbols A_s_c, A_d A = −A_i
  std::vector<std::vector<GiNaC::ex>> M;     // (n × n) [Cᵀ M; B]
  std::vector<GiNaC::ex> f;                  // (n) [Cᵀ f; −(Ḃ u + ċ)]
};

// From the engine's data after CalcKinematics, CalcMassMatrix* and CalcForcing on Symbolic at
// the symbols u (n), with M and f the tree's (n × n, n). The A symbols are named "A_s_c"
// (1-based), with '_' appended while a name is in `reserved`, or are same_A's (a derivation of
// the same model, equations.h) where it has one. Throws ModelError if the
// dependent speeds cannot be chosen (redundant constraints at the initial state).
ConstrainedEquations DeriveConstrained(const multibody::Model& model,
                                       multibody::Data<multibody::Symbolic>& data,
                                       const std::vector<GiNaC::ex>& u,
                                       const std::vector<std::vector<GiNaC::ex>>& M,
                                       const std::vector<GiNaC::ex>& f,
                                       const std::set<std::string>& reserved,
                                       const std::vector<std::vector<GiNaC::ex>>* same_A = nullptr);

// Every expression of c (not the A symbols), in a fixed order: A_d, A_i by rows, b, bias, M by
// rows, f.
std::vector<GiNaC::ex*> ConstrainedOutputs(ConstrainedEquations& c);

}  // namespace hybridtest::symbolic
