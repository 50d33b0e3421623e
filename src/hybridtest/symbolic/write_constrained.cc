// The constrained part of the equations document. See write_constrained.h.
#include "hybridtest/symbolic/write_constrained.h"

#include <fmt/core.h>

namespace hybridtest::symbolic {

namespace {

constexpr const char* kConstrainedNote =
    "The constraints split the speeds into dependent ones u_d and independent ones u_i: "
    "A_d u_d + A_i u_i + b = 0 (velocity level), B u̇ + (Ḃ u + ċ) = 0 (acceleration level, "
    "B = [A_d A_i] in the speeds' order). A = −A_d⁻¹ A_i is not inverted symbolically: its "
    "entries A_s_c are symbols, at a state the solution of A_d A = −A_i. With C the matrix "
    "whose rows are I (independent speeds) and A (dependent speeds), the reduced equations are "
    "[Cᵀ M; B] u̇ = [Cᵀ f; −(Ḃ u + ċ)], rows: the independent speeds, then the constraint rows "
    "(the engine's, as `eom --assemble` prints them, unstabilised).";

constexpr const char* kConstrainedNoteLatex =
    "The constraints split the speeds into dependent ones $u_d$ and independent ones $u_i$: "
    "$A_d u_d + A_i u_i + b = 0$ (velocity level), $B \\dot u + (\\dot B u + \\dot c) = 0$ "
    "(acceleration level, $B = [A_d\\ A_i]$ in the speeds' order). $A = -A_d^{-1} A_i$ is not "
    "inverted symbolically: its entries $A_{s,c}$ are symbols, at a state the solution of "
    "$A_d A = -A_i$. With $C$ the matrix whose rows are $I$ (independent speeds) and $A$ "
    "(dependent speeds), the reduced equations are $M_r \\dot u = f_r$, $M_r = [C^T M; B]$, "
    "$f_r = [C^T f; -(\\dot B u + \\dot c)]$, rows: the independent speeds, then the "
    "constraint rows (the engine's, as \\texttt{eom --assemble} prints them, unstabilised).";

std::string SpeedList(const multibody::Model& model, const std::vector<int>& speeds) {
  std::string s;
  for (int j : speeds) s += (s.empty() ? "" : ", ") + model.speeds()[static_cast<std::size_t>(j)].name;
  return s;
}

std::string DependentSource(const multibody::Model& model) {
  return model.constraint_options().dependent_speeds.empty()
             ? "picked by the engine's pivoting at the model's initial state"
             : "the model's dependent_speeds";
}

}  // namespace

void AddConstrainedNames(const ConstrainedEquations& c, Dialect dialect, NameMap& names) {
  for (std::size_t s = 0; s < c.A.size(); ++s) {
    for (std::size_t k = 0; k < c.A[s].size(); ++k) {
      const std::string name = GiNaC::ex_to<GiNaC::symbol>(c.A[s][k]).get_name();
      names[name] = dialect == Dialect::kLatex ? fmt::format("A_{{{},{}}}", s + 1, k + 1)
                    : dialect == Dialect::kSympy ? PythonName(name) : name;
    }
  }
}

std::string ConstrainedMarkdown(const multibody::Model& model, const ConstrainedEquations& c,
                                const NameMap& names) {
  auto P = [&](const GiNaC::ex& e) {
    return fmt::format("`{}`", PrintExpression(e, Dialect::kPlain, names));
  };
  std::string s = fmt::format("\n## Constraints and the reduced equations\n\n{}\n\nDependent "
                              "speeds u_d: {} ({}); independent speeds u_i: {}.\n",
                              kConstrainedNote, SpeedList(model, c.dependent), DependentSource(model),
                              SpeedList(model, c.independent));
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    s += fmt::format("\nRow {} ({}):\n\n", r + 1, c.rows[r]);
    for (std::size_t k = 0; k < c.A_d[r].size(); ++k) {
      if (!c.A_d[r][k].is_zero()) s += fmt::format("- A_d[{},{}] = {}\n", r + 1, k + 1, P(c.A_d[r][k]));
    }
    for (std::size_t k = 0; k < c.A_i[r].size(); ++k) {
      if (!c.A_i[r][k].is_zero()) s += fmt::format("- A_i[{},{}] = {}\n", r + 1, k + 1, P(c.A_i[r][k]));
    }
    s += fmt::format("- b[{}] = {}\n- (Ḃ u + ċ)[{}] = {}\n", r + 1, P(c.b[r]), r + 1, P(c.bias[r]));
  }
  s += "\nReduced mass matrix [Cᵀ M; B] (the entries that are not zero):\n\n";
  for (std::size_t j = 0; j < c.M.size(); ++j)
    for (std::size_t k = 0; k < c.M[j].size(); ++k)
      if (!c.M[j][k].is_zero()) s += fmt::format("- M_r[{},{}] = {}\n", j + 1, k + 1, P(c.M[j][k]));
  s += "\nReduced forcing [Cᵀ f; −(Ḃ u + ċ)]:\n\n";
  for (std::size_t j = 0; j < c.f.size(); ++j) s += fmt::format("- f_r{} = {}\n", j + 1, P(c.f[j]));
  return s;
}

std::string ConstrainedLatex(const multibody::Model& model, const ConstrainedEquations& c,
                             const NameMap& names) {
  auto L = [&](const GiNaC::ex& e) { return PrintExpression(e, Dialect::kLatex, names); };
  std::string s = fmt::format("\\subsection*{{Constraints and the reduced equations}}\n{}\n\n"
                              "Dependent speeds $u_d$: {} ({}); independent speeds $u_i$: {}.\n"
                              "\\begin{{align*}}\n", kConstrainedNoteLatex,
                              LatexText(SpeedList(model, c.dependent)), LatexText(DependentSource(model)),
                              LatexText(SpeedList(model, c.independent)));
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    for (std::size_t k = 0; k < c.A_d[r].size(); ++k) {
      if (!c.A_d[r][k].is_zero()) s += fmt::format("  A_{{d,{},{}}} &= {} \\\\\n", r + 1, k + 1, L(c.A_d[r][k]));
    }
    for (std::size_t k = 0; k < c.A_i[r].size(); ++k) {
      if (!c.A_i[r][k].is_zero()) s += fmt::format("  A_{{i,{},{}}} &= {} \\\\\n", r + 1, k + 1, L(c.A_i[r][k]));
    }
    s += fmt::format("  b_{{{0}}} &= {1} \\\\\n  (\\dot B u + \\dot c)_{{{0}}} &= {2} \\\\\n", r + 1,
                     L(c.b[r]), L(c.bias[r]));
  }
  s += "\\end{align*}\nReduced equations $M_r \\dot u = f_r$:\n\\begin{align*}\n";
  for (std::size_t j = 0; j < c.M.size(); ++j)
    for (std::size_t k = 0; k < c.M[j].size(); ++k)
      if (!c.M[j][k].is_zero()) s += fmt::format("  M_{{r,{},{}}} &= {} \\\\\n", j + 1, k + 1, L(c.M[j][k]));
  for (std::size_t j = 0; j < c.f.size(); ++j) s += fmt::format("  f_{{r,{}}} &= {} \\\\\n", j + 1, L(c.f[j]));
  s += "\\end{align*}\n";
  return s;
}

std::string ConstrainedSympySymbols(const ConstrainedEquations& c, const NameMap& names) {
  std::string s;
  for (const auto& row : c.A) {
    for (const GiNaC::ex& a : row) {
      const std::string name = GiNaC::ex_to<GiNaC::symbol>(a).get_name();
      s += fmt::format("{} = sp.Symbol({}, real=True)  # entry of A = -A_d^-1 A_i\n",
                       names.at(name), PythonString(name));
    }
  }
  return s;
}

std::string ConstrainedSympy(const multibody::Model& model, const ConstrainedEquations& c,
                             const NameMap& names) {
  auto Y = [&](const GiNaC::ex& e) { return PrintExpression(e, Dialect::kSympy, names); };
  auto list = [&](const std::vector<GiNaC::ex>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Y(v[i]);
    return s + "]";
  };
  auto matrix = [&](const std::vector<std::vector<GiNaC::ex>>& rows) {
    std::string s = "sp.Matrix([\n";
    for (const auto& row : rows) s += "    " + list(row) + ",\n";
    return s + "])\n";
  };
  auto speeds = [&](const std::vector<int>& indices) {
    std::string s = "[";
    for (std::size_t i = 0; i < indices.size(); ++i) {
      s += (i ? ", " : "") + names.at(model.speeds()[static_cast<std::size_t>(indices[i])].name);
    }
    return s + "]";
  };
  std::string rows = "[";
  for (std::size_t r = 0; r < c.rows.size(); ++r) rows += (r ? ", " : "") + PythonString(c.rows[r]);
  rows += "]";
  std::string s = fmt::format("\n# Constraints. {}\n# Dependent speeds: {}.\n", PythonComment(kConstrainedNote),
                              PythonComment(DependentSource(model)));
  s += fmt::format("dependent = {}\nindependent = {}\nconstraint_rows = {}\n", speeds(c.dependent),
                   speeds(c.independent), rows);
  s += "A_d = " + matrix(c.A_d) + "A_i = " + matrix(c.A_i);
  s += fmt::format("b = sp.Matrix({})\nbias = sp.Matrix({})  # B u' + bias = 0\n", list(c.b), list(c.bias));
  s += "A = " + matrix(c.A) + "M_reduced = " + matrix(c.M);
  s += fmt::format("f_reduced = sp.Matrix({})\n", list(c.f));
  return s;
}

}  // namespace hybridtest::symbolic
