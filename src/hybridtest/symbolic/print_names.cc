// Names and text for LaTeX and Python: the helpers print_expression.h declares besides
// PrintExpression (LatexName, LatexText, PythonString*, PythonComment, PythonName).
#include <fmt/core.h>

#include <cctype>
#include <set>
#include <string>
#include <string_view>

#include "hybridtest/symbolic/print_expression.h"

namespace hybridtest::symbolic {

std::string LatexName(const std::string& name) {
  static const std::set<std::string> kGreek = {
      "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa",
      "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "phi", "chi", "psi", "omega",
      "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Phi", "Psi", "Omega"};
  std::string base = name;
  bool dot = false;
  if (base.size() > 4 && base.substr(base.size() - 4) == "_dot") {
    dot = true;
    base = base.substr(0, base.size() - 4);
  }
  std::string sub;
  const auto underscore = base.find('_');
  if (underscore != std::string::npos) {
    sub = base.substr(underscore + 1);
    base = base.substr(0, underscore);
  } else {
    std::size_t digits = base.size();
    while (digits > 1 && std::isdigit(static_cast<unsigned char>(base[digits - 1]))) --digits;
    sub = base.substr(digits);
    base = base.substr(0, digits);
  }
  auto escape = [&](std::string s) {
    if (kGreek.count(s)) return "\\" + s;
    const std::string out = LatexText(s);
    return s.size() > 1 ? "\\mathrm{" + out + "}" : out;
  };
  std::string text = escape(base);
  if (dot) text = "\\dot{" + text + "}";
  if (!sub.empty()) text += "_{" + escape(sub) + "}";
  return text;
}

std::string LatexText(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '\\': out += "\\textbackslash{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '~': out += "\\textasciitilde{}"; break;
      case '{': case '}': case '$': case '&': case '#': case '%': case '_':
        out += '\\';
        out += c;
        break;
      default:
        out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? ' ' : c;
    }
  }
  return out;
}

std::string PythonStringBody(std::string_view text) {
  std::string out;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\\' || c == '\'' || c == '"') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u == 0x7f) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned>(u));
    } else {
      out += c;
    }
  }
  return out;
}

std::string PythonString(std::string_view text) {
  std::string out(1, '\'');
  out += PythonStringBody(text);
  out += '\'';
  return out;
}

std::string PythonComment(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return out;
}

std::string PythonName(const std::string& name) {
  static const std::set<std::string> kReserved = {
      "sp", "sympy", "q", "u", "r", "t", "z", "M", "f", "Fr", "Fr_star", "udot", "qdot",
      "parameters", "zdot", "M_paper", "g_paper", "dependent", "independent",
      "constraint_rows", "A", "A_d", "A_i", "b", "bias", "M_reduced", "f_reduced", "False", "None", "True", "and", "as", "assert", "async", "await", "break",
      "class", "continue", "def", "del", "elif", "else", "except", "finally", "for", "from",
      "global", "if", "import", "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise",
      "return", "try", "while", "with", "yield"};
  std::string s;
  for (char c : name) s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "_" + s;
  while (kReserved.count(s)) s += "_";
  return s;
}

}  // namespace hybridtest::symbolic
