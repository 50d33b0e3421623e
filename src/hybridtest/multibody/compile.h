#pragma once
// What Build() derives from the user's specs (model.h) for the engine: the compiled frames and
// points, the mass terms and the structure of the mass matrix's Cholesky factor. The specs
// themselves are only read.
#include <vector>

#include "hybridtest/multibody/model.h"

namespace hybridtest::multibody::internal {

struct CompiledKinematics {
  std::vector<CompiledFrame> frames;  // indexed like ModelElements::frames
  std::vector<CompiledPoint> points;  // indexed like ModelElements::points
  // Some expression is general (not affine), a frame has a DCM, or q̇ = W(q) u.
  bool general = false;
  // 0, 1 or 2 if the model is planar about that axis of N (Model::planar_axis()), else −1.
  int planar_axis = -1;
};

// Active speeds (frames first: parents precede children by construction), the constant
// rotations, and the affine fast paths.
CompiledKinematics CompileKinematics(const ModelElements& elements);

// Translational mass terms: every pair j ≤ k of each point mass's active speeds.
std::vector<MassTerm> CompileMassTerms(const ModelElements& elements,
                                       const std::vector<CompiledPoint>& points);

// The structurally non-zero entries of M (n × n column-major, lower triangle): the mass
// terms, the bodies' rotational pairs, the tree plan's pairs.
std::vector<char> CompileMassStructure(const ModelElements& elements,
                                       const std::vector<CompiledFrame>& frames,
                                       const std::vector<MassTerm>& mass_terms,
                                       const TreeMassPlan& plan);

// The structure of L in M = L Lᵀ: `structure` and the fill-in of the elimination.
std::vector<char> CompileFactorPattern(std::vector<char> structure, int n);

// The sparse factorisation's plan for M's `structure` (CompileMassStructure's), or an
// empty plan if the dense solve is the better choice (n ≤ 6, or L more than half full in
// either order).
SparseFactorPlan CompileSparseFactor(const std::vector<char>& structure, int n);

// The constant entries of a planar model's mass matrix and the columns of its factor that
// follow from them (constant_mass.h). Empty (no constant entry) unless the model is planar
// (`planar_axis` ≥ 0) and n ≤ 6 (the fixed-size factor kernels); `factor_pattern` is
// CompileFactorPattern's.
ConstantMassPlan CompileConstantMass(const ModelElements& elements,
                                     const std::vector<CompiledFrame>& frames,
                                     const std::vector<CompiledPoint>& points, int planar_axis,
                                     const std::vector<char>& factor_pattern);

}  // namespace hybridtest::multibody::internal
