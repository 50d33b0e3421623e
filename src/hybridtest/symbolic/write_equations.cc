// Markdown, LaTeX and SymPy documents of a model's equations. See write_equations.h.
#include "hybridtest/symbolic/write_equations.h"

#include <fmt/core.h>

#include <set>

#include "hybridtest/symbolic/print_expression.h"
#include "hybridtest/symbolic/write_constrained.h"

namespace hybridtest::symbolic {

namespace {

constexpr const char* kConvention =
    "M(q, t) u̇ = f(q, u, t, r): SymPy's convention (KanesMethod: mass_matrix · u̇ = forcing), "
    "M symmetric positive definite, f = Fr + (Fr* without its u̇ terms). Vectors are in "
    "components of the Newtonian frame N. Model parameters appear as symbols where the engine's "
    "number is a product of their powers (checked by rebuilding the model), otherwise as "
    "numbers in SI (the table lists their values).";

struct Symbol {
  std::string name;  // as the model names it
  std::string kind;  // coordinate, speed, ...
  std::string unit;
  std::string description;
};

std::vector<Symbol> Symbols(const multibody::Model& model) {
  std::vector<Symbol> s;
  for (const auto& c : model.coordinates()) s.push_back({c.name, "coordinate", c.unit, c.description});
  for (const auto& c : model.speeds()) s.push_back({c.name, "speed", c.unit, c.description});
  for (const auto& c : model.speeds()) {
    s.push_back({c.name + "_dot", "speed rate", c.unit + "/s", "rate of " + c.name});
  }
  for (const auto& c : model.slots()) {
    s.push_back({c.info.name, "restoring force", c.info.unit.empty() ? "N" : c.info.unit,
                 c.info.description});
  }
  for (const auto& c : model.extra_states()) {
    s.push_back({c.info.name, "extra state", c.info.unit, c.info.description});
  }
  s.push_back({"t", "time", "s", "time"});
  return s;
}

NameMap Names(const std::vector<Symbol>& symbols, Dialect d) {
  NameMap names;
  for (const Symbol& s : symbols) {
    if (d == Dialect::kLatex) names[s.name] = LatexName(s.name);
    if (d == Dialect::kSympy) names[s.name] = s.name == "t" && s.kind == "time" ? "t" : PythonName(s.name);
    if (d == Dialect::kPlain) names[s.name] = s.name;
  }
  return names;
}

// The symbols' names and the parameters' (a parameter named like a symbol keeps the symbol's).
NameMap Names(const std::vector<Symbol>& symbols, const DocumentInfo& info, Dialect d,
              const Equations& eq) {
  NameMap names = Names(symbols, d);
  AddConstrainedNames(eq.constrained, d, names);
  for (const auto& p : info.parameters) {
    if (names.count(p.name) > 0) continue;
    names[p.name] = d == Dialect::kLatex ? LatexName(p.name)
                    : d == Dialect::kSympy ? PythonName(p.name) : p.name;
  }
  return names;
}

std::string Vector3Text(const std::vector<GiNaC::ex>& v, Dialect d, const NameMap& names) {
  const std::string a = PrintExpression(v[0], d, names), b = PrintExpression(v[1], d, names),
                    c = PrintExpression(v[2], d, names);
  if (d == Dialect::kLatex) {
    return fmt::format("\\begin{{bmatrix}} {} \\\\ {} \\\\ {} \\end{{bmatrix}}_N", a, b, c);
  }
  return fmt::format("`[{}, {}, {}]` (N)", a, b, c);
}

// A long LaTeX sum over several lines of an align* (three terms a line).
std::string LatexBroken(const GiNaC::ex& e, const NameMap& names) {
  if (!GiNaC::is_a<GiNaC::add>(e) || e.nops() <= 4) return PrintExpression(e, Dialect::kLatex, names);
  std::string text;
  const std::vector<std::string> terms = PrintTerms(e, Dialect::kLatex, names);
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const std::string& term = terms[i];
    if (i > 0 && i % 3 == 0) text += " \\\\\n  &\\quad ";
    if (i == 0) {
      text += term;
    } else if (!term.empty() && term[0] == '-') {
      text += " - " + term.substr(1);
    } else {
      text += " + " + term;
    }
  }
  return text;
}

// A parameter's value as the expressions print numbers (at most 15 significant digits: 2π/3
// as 2.0943951023932, not with the last bits of the builder's arithmetic).
std::string Value(double v, Dialect d) { return PrintExpression(GiNaC::numeric(v), d, {}); }

// What the common subexpressions are (printed above them).
constexpr const char* kSharedNote =
    "These equations are too large to expand (docs/equations.md, \"Large models\"): they are "
    "the engine's own expressions, each subexpression used more than once computed once below, "
    "in order, with the model's parameters as their values in SI.";

std::string Markdown(const multibody::Model& model, const Equations& eq, const DocumentInfo& info) {
  const auto symbols = Symbols(model);
  const NameMap names = Names(symbols, info, Dialect::kPlain, eq);
  auto P = [&](const GiNaC::ex& e) {
    return fmt::format("`{}`", PrintExpression(e, Dialect::kPlain, names));
  };
  const int n = model.num_coordinates();
  std::string s = fmt::format("# Equations of motion: {}\n\n{}. Derived by hybridtest's Kane "
                              "engine (the code that computes them numerically) from `{}`.\n\n"
                              "Convention: {}\n\n## Symbols\n\n| symbol | kind | unit | meaning |\n"
                              "|---|---|---|---|\n", info.model_name, info.description,
                              info.source, kConvention);
  for (const Symbol& sym : symbols) {
    s += fmt::format("| `{}` | {} | {} | {} |\n", sym.name, sym.kind, sym.unit, sym.description);
  }
  s += "\n## Parameters (values used)\n\n| parameter | value | unit | meaning |\n|---|---|---|---|\n";
  for (const auto& p : info.parameters) {
    s += fmt::format("| `{}` | {} | {} | {} |\n", p.name, Value(p.value, Dialect::kPlain), p.unit,
                     p.description);
  }
  if (!eq.shared.definitions.empty()) {
    s += fmt::format("\n## Common subexpressions\n\n{}\n\n", kSharedNote);
    for (const auto& [symbol, value] : eq.shared.definitions) {
      s += fmt::format("- {} = {}\n", PrintExpression(symbol, Dialect::kPlain, names), P(value));
    }
  }
  s += "\n## Kinematical equations q̇ = W(q) u\n\n";
  for (int k = 0; k < n; ++k) s += fmt::format("- d{}/dt = {}\n", model.coordinates()[k].name, P(eq.qdot[k]));
  for (std::size_t k = 0; k < eq.zdot.size(); ++k) {
    s += fmt::format("- d{}/dt = {}\n", model.extra_states()[k].info.name, P(eq.zdot[k]));
  }
  auto partials = [&](const std::vector<NamedPartials>& list, const char* kind, const char* v) {
    for (const NamedPartials& np : list) {
      s += fmt::format("\n{} {}:\n\n", kind, np.name);
      for (int j = 0; j < n; ++j) {
        const auto& c = np.columns[j];
        if (c[0].is_zero() && c[1].is_zero() && c[2].is_zero()) continue;
        s += fmt::format("- ∂{}/∂{} = {}\n", v, model.speeds()[j].name,
                         Vector3Text(c, Dialect::kPlain, names));
      }
    }
  };
  s += "\n## Partial angular velocities (Kane's step v)\n";
  partials(eq.frame_partials, "Frame", "ω");
  s += "\n## Partial velocities (Kane's step v)\n";
  partials(eq.point_partials, "Point", "v");
  s += "\n## Generalized active forces Fr (step vi)\n\n";
  for (int j = 0; j < n; ++j) s += fmt::format("- F{} = {}\n", j + 1, P(eq.Fr[j]));
  s += "\n## Generalized inertia forces Fr* (step vii)\n\n";
  for (int j = 0; j < n; ++j) s += fmt::format("- F{}* = {}\n", j + 1, P(eq.Fr_star[j]));
  s += "\n## Equations of motion M u̇ = f (Fr + Fr* = 0)\n\nMass matrix M (symmetric; the "
       "entries on and above the diagonal that are not zero):\n\n";
  for (int j = 0; j < n; ++j)
    for (int k = j; k < n; ++k)
      if (!eq.M[j][k].is_zero()) s += fmt::format("- M[{},{}] = {}\n", j + 1, k + 1, P(eq.M[j][k]));
  s += "\nForcing f:\n\n";
  for (int j = 0; j < n; ++j) s += fmt::format("- f{} = {}\n", j + 1, P(eq.f[j]));
  if (model.has_constraints()) s += ConstrainedMarkdown(model, eq.constrained, names);
  if (info.paper_form) {
    s += fmt::format("\n## The paper's form M_p ẋ + g_p = 0 (Eq. 18)\n\nx = [q; u], M_p = "
                     "blockdiag(I_{0}, −M) ({1} × {1}), g_p = [−q̇; f]: the lower block of M_p "
                     "is −M above, the entries of g_p are\n\n", n, 2 * n);
    for (int k = 0; k < n; ++k) s += fmt::format("- g_p[{}] = {}\n", k + 1, P(-eq.qdot[k]));
    for (int k = 0; k < n; ++k) s += fmt::format("- g_p[{}] = {}\n", n + k + 1, P(eq.f[k]));
  }
  return s;
}

std::string Latex(const multibody::Model& model, const Equations& eq, const DocumentInfo& info) {
  const auto symbols = Symbols(model);
  const NameMap names = Names(symbols, info, Dialect::kLatex, eq);
  auto L = [&](const GiNaC::ex& e) { return PrintExpression(e, Dialect::kLatex, names); };
  auto text = [](const std::string& s) { return LatexText(s); };
  const int n = model.num_coordinates();
  std::string s = "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n"
                  "\\usepackage{amsmath}\n\\allowdisplaybreaks\n\\begin{document}\n";
  s += fmt::format("\\section*{{Equations of motion: {}}}\n{}. Derived by hybridtest's Kane "
                   "engine from \\texttt{{{}}}. Convention: $M(q, t)\\,\\dot u = f(q, u, t, r)$ "
                   "(SymPy's), $M$ symmetric positive definite; vectors in components of the "
                   "Newtonian frame $N$; parameters appear as symbols where the engine's number is a "
                   "product of their powers, otherwise as their values in SI.\n\n",
                   text(info.model_name), text(info.description), text(info.source));
  if (!eq.shared.definitions.empty()) {
    s += fmt::format("\\subsection*{{Common subexpressions}}\n{}\n\\begin{{align*}}\n",
                     LatexText(kSharedNote));
    for (const auto& [symbol, value] : eq.shared.definitions) {
      s += fmt::format("  {} &= {} \\\\\n", L(symbol), LatexBroken(value, names));
    }
    s += "\\end{align*}\n";
  }
  s += "\\subsection*{Kinematical equations}\n\\begin{align*}\n";
  for (int k = 0; k < n; ++k) {
    s += fmt::format("  \\dot{{{}}} &= {} \\\\\n", LatexName(model.coordinates()[k].name), L(eq.qdot[k]));
  }
  s += "\\end{align*}\n";
  auto partials = [&](const std::vector<NamedPartials>& list, const char* title, const char* v) {
    s += fmt::format("\\subsection*{{{}}}\n", title);
    for (const NamedPartials& np : list) {
      s += fmt::format("\\paragraph{{{}}}\n\\begin{{align*}}\n", text(np.name));
      for (int j = 0; j < n; ++j) {
        const auto& c = np.columns[j];
        if (c[0].is_zero() && c[1].is_zero() && c[2].is_zero()) continue;
        s += fmt::format("  \\frac{{\\partial {}}}{{\\partial {}}} &= {} \\\\\n", v,
                         LatexName(model.speeds()[j].name), Vector3Text(c, Dialect::kLatex, names));
      }
      s += "\\end{align*}\n";
    }
  };
  partials(eq.frame_partials, "Partial angular velocities", "\\omega");
  partials(eq.point_partials, "Partial velocities", "v");
  auto list = [&](const char* title, const std::vector<GiNaC::ex>& v, const char* name) {
    s += fmt::format("\\subsection*{{{}}}\n\\begin{{align*}}\n", title);
    for (int j = 0; j < n; ++j) s += fmt::format("  {}_{{{}}} &= {} \\\\\n", name, j + 1, LatexBroken(v[j], names));
    s += "\\end{align*}\n";
  };
  list("Generalized active forces", eq.Fr, "F");
  list("Generalized inertia forces", eq.Fr_star, "F^*");
  s += "\\subsection*{Equations of motion $M \\dot u = f$}\n\\begin{align*}\n";
  for (int j = 0; j < n; ++j)
    for (int k = j; k < n; ++k)
      if (!eq.M[j][k].is_zero()) s += fmt::format("  M_{{{},{}}} &= {} \\\\\n", j + 1, k + 1, LatexBroken(eq.M[j][k], names));
  s += "\\end{align*}\nThe other entries follow from $M = M^T$ or are zero.\n\\begin{align*}\n";
  for (int j = 0; j < n; ++j) s += fmt::format("  f_{{{}}} &= {} \\\\\n", j + 1, LatexBroken(eq.f[j], names));
  s += "\\end{align*}\n";
  if (model.has_constraints()) s += ConstrainedLatex(model, eq.constrained, names);
  if (info.paper_form) {
    s += fmt::format("\\subsection*{{The paper's form $M_p \\dot x + g_p = 0$ (Eq.~18)}}\n"
                     "$x = [q; u]$, $M_p = \\mathrm{{blockdiag}}(I_{{{}}}, -M)$, $g_p = [-\\dot q; f]$.\n", n);
  }
  s += "\\end{document}\n";
  return s;
}

std::string Sympy(const multibody::Model& model, const Equations& eq, const DocumentInfo& info) {
  const auto symbols = Symbols(model);
  const NameMap names = Names(symbols, info, Dialect::kSympy, eq);
  std::set<std::string> symbol_names;
  for (const Symbol& sym : symbols) symbol_names.insert(sym.name);
  auto Y = [&](const GiNaC::ex& e) { return PrintExpression(e, Dialect::kSympy, names); };
  auto list = [&](const std::vector<GiNaC::ex>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Y(v[i]);
    return s + "]";
  };
  std::string s = fmt::format("\"\"\"Equations of motion of {}, from hybridtest's Kane engine "
                              "({}).\n\nConvention: {}\n\"\"\"\nimport sympy as sp\n\n",
                              PythonStringBody(info.model_name),
                              PythonStringBody(info.source), kConvention);
  for (const Symbol& sym : symbols) {
    s += fmt::format("{} = sp.Symbol({}, real=True)  # {} [{}]\n", names.at(sym.name),
                     PythonString(sym.name), sym.kind, PythonComment(sym.unit));
  }
  for (const auto& p : info.parameters) {
    if (symbol_names.count(p.name) > 0) continue;
    s += fmt::format("{} = sp.Symbol({}, real=True)  # parameter [{}]\n", names.at(p.name),
                     PythonString(p.name), PythonComment(p.unit));
  }
  s += ConstrainedSympySymbols(eq.constrained, names);
  if (!eq.shared.definitions.empty()) {
    s += fmt::format("\n# Common subexpressions. {}\n", PythonComment(kSharedNote));
    for (const auto& [symbol, value] : eq.shared.definitions) {
      s += fmt::format("{} = {}\n", Y(symbol), Y(value));
    }
  }
  s += fmt::format("\nq = {}\nu = {}\nudot = {}\nr = {}\nz = {}\n", list(eq.q), list(eq.u),
                   list(eq.udot), list(eq.r), list(eq.z));
  s += fmt::format("qdot = sp.Matrix({})\n", list(eq.qdot));
  if (!eq.zdot.empty()) s += fmt::format("zdot = sp.Matrix({})\n", list(eq.zdot));
  s += "M = sp.Matrix([\n";
  for (const auto& row : eq.M) s += "    " + list(row) + ",\n";
  s += "])\n";
  s += fmt::format("f = sp.Matrix({})\nFr = sp.Matrix({})\nFr_star = sp.Matrix({})\n",
                   list(eq.f), list(eq.Fr), list(eq.Fr_star));
  if (model.has_constraints()) s += ConstrainedSympy(model, eq.constrained, names);
  if (info.paper_form) {
    s += "M_paper = sp.diag(sp.eye(len(q)), -M)  # the paper's M_p x' + g_p = 0 (Eq. 18)\n"
         "g_paper = sp.Matrix.vstack(-qdot, f)\n";
  }
  s += "\n# The model's parameters and their values in SI: M.subs(parameters) is numeric in "
       "everything but t, q, u, r, z.\nparameters = {\n";
  for (const auto& p : info.parameters) {
    if (symbol_names.count(p.name) > 0) continue;  // named like a symbol: printed as its value
    s += fmt::format("    {}: {},\n", names.at(p.name), Value(p.value, Dialect::kSympy));
  }
  s += "}\n";
  return s;
}

}  // namespace

std::string WriteEquations(const multibody::Model& model, const Equations& eq,
                           const DocumentInfo& info, Format format) {
  switch (format) {
    case Format::kLatex: return Latex(model, eq, info);
    case Format::kSympy: return Sympy(model, eq, info);
    default: return Markdown(model, eq, info);
  }
}

}  // namespace hybridtest::symbolic
