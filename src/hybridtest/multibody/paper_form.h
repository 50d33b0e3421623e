#pragma once
// The paper's form of the equations of motion (Eq. 18), from the engine's Kane form.
//
// The engine assembles Kane's equations as SymPy does (kane.h): M u̇ = g_K with M symmetric
// positive definite, and q̇ = W(q) u. The paper stacks x = [q; u] (2n) and writes
//
//   M_paper ẋ + g_paper = 0                                                  (Eq. 18)
//
//   M_paper = ⎡ I_n   0 ⎤   (2n × 2n)        g_paper = ⎡ −W u ⎤   (2n)
//             ⎣ 0    −M ⎦                              ⎣  g_K ⎦
//
// so that ẋ = −M_paper⁻¹ g_paper = [W u; M⁻¹ g_K] (Eq. 21). For the rotor the lower block of
// M_paper is the paper's Eq. (19) (the negative arrow matrix). The lower block of g_paper is
// NOT the printed Eq. (20), which has a sign error in the hub row's Coriolis term (see
// tests/multibody/paper_form_test.cc and shared PAPER-NOTES); it is derived, not transcribed.
//
// This is a boundary conversion for reports and comparisons with the paper; the simulation
// itself uses CalcStateDerivative. It allocates (returns new matrices).
#include <Eigen/Core>

#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody {

struct PaperForm {
  Eigen::MatrixXd M;  // (2n × 2n) blockdiag(I_n, −M_Kane); mixed units (1, kg, kg·m, kg·m²)
  Eigen::VectorXd g;  // (2n) [−W u; g_K]; units of −q̇ ([m/s], [rad/s]) then of g_K ([N], [N·m])
};

// Builds the paper's form from `data` after CalcStateDerivative, or after CalcKinematics +
// CalcMassMatrix + CalcForcing at the same state (it reads data.W, data.u, data.M, data.g).
PaperForm PaperFormFromKane(const Data<double>& data);

}  // namespace hybridtest::multibody
