#pragma once
// Internal to the engine: M u̇ = g by a Cholesky factorisation M = L Lᵀ, in two steps so that
// the factorisation can run as soon as M is known. CalcStateDerivative factors M before it
// computes the forcing: the square roots and divisions of the factor, which the forcing does
// not need, then overlap with the forcing's work instead of ending the evaluation's chain of
// dependencies. The operations are the same as a factor-and-solve in one go (bit for bit).
//
// Which kernel (see decision 0012): the model's sparse plan if it has one
// (Model::sparse_factor()); otherwise unrolled for n ≤ 6 (skipping the structural zeros of
// Model::factor_pattern()), a plain loop for 7 ≤ n < 24, Eigen's blocked LLT from 24 (doubles).
#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody::internal {

// Factors data.M into data.cholesky_factor (row i of L is its contiguous column i; the blocked
// path keeps Eigen's lower-triangular layout) and 1/L_ii into data.factor_inv_diag. Reads M's
// lower triangle only. Returns false if M is not positive definite.
template <typename T>
bool FactorMassMatrix(const Model& model, Data<T>& data);

// data.udot = M⁻¹ data.g with the factor of the last FactorMassMatrix.
template <typename T>
void SolveFactoredMassMatrix(const Model& model, Data<T>& data);

}  // namespace hybridtest::multibody::internal
