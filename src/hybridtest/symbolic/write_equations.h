#pragma once
// The equations of a model as a document: Markdown (for a report), LaTeX (a complete article
// that pdflatex compiles) or a SymPy module (docs/equations.md shows all three).
//
// Contents, in Kane's order (the paper's Section 2): the symbols, the parameters, the
// kinematical equations q̇ = W(q) u, the partial velocities and partial angular velocities
// (step v), the generalized active forces Fr and inertia forces Fr* (steps vi–vii), and the
// equations of motion M(q, t) u̇ = f(q, u, t, r) (SymPy's convention). With `paper_form`,
// also the paper's M_p ẋ + g_p = 0 (Eq. 18): M_p = blockdiag(I, −M), g_p = [−q̇; f].
//
// The SymPy module defines, when executed: `sp` (sympy), one variable per symbol, `t`, the
// lists `q`, `u`, `r`, `z`, `udot`, `qdot`, `M` and `f` (sympy.Matrix, M u̇ = f), `Fr`,
// `Fr_star` (sympy.Matrix) and `parameters` (dict: parameter symbol → value in SI).
#include <string>
#include <vector>

#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/equations.h"

namespace hybridtest::symbolic {

enum class Format { kMarkdown, kLatex, kSympy };

struct ParameterEntry {
  std::string name;
  double value = 0.0;  // SI
  std::string unit;
  std::string description;
};

struct DocumentInfo {
  std::string model_name;
  std::string description;
  std::string source;  // the file or built-in name the model came from
  std::vector<ParameterEntry> parameters;
  bool paper_form = false;
};

std::string WriteEquations(const multibody::Model& model, const Equations& eq,
                           const DocumentInfo& info, Format format);

}  // namespace hybridtest::symbolic
