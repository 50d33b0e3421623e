#pragma once
// The O(n·depth) mass matrix of a tree of joints (decision 0012; TreeMassPlan in model.h):
// the planner that decides at Build() whether a model qualifies, and the evaluation.
#include <string>
#include <vector>

#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody::internal {

// Fills `plan` and returns "" if the model is a tree of joints with q̇ = u (every coordinate
// is the angle of exactly one affine frame, or appears in the position of exactly one point;
// every point and body moved by a revolute joint is moved rigidly about one pivot; the sets of
// mass elements the speeds move are nested or disjoint). Otherwise returns why not (the
// model then takes the pairwise path).
std::string PlanTreeMassMatrix(const ModelElements& elements,
                               const std::vector<CompiledFrame>& frames,
                               const std::vector<CompiledPoint>& points, TreeMassPlan& plan);

// data.M by the plan, from the last CalcKinematics.
template <typename T>
void CalcTreeMassMatrix(const Model& model, Data<T>& data);

}  // namespace hybridtest::multibody::internal
