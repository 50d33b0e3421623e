// Unit parsing for model files. See units.h.
#include "hybridtest/modelfile/units.h"

#include <fmt/core.h>

#include <cmath>
#include <numbers>

namespace hybridtest::modelfile {
namespace {

struct KnownUnit {
  const char* name;
  double to_si;
  std::array<int, 4> dim;  // m, kg, s, rad
  const char* si;          // its SI counterpart, written as a unit
};

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr KnownUnit kUnits[] = {
    {"m", 1.0, {1, 0, 0, 0}, "m"},         {"mm", 1e-3, {1, 0, 0, 0}, "m"},
    {"cm", 1e-2, {1, 0, 0, 0}, "m"},       {"km", 1e3, {1, 0, 0, 0}, "m"},
    {"µm", 1e-6, {1, 0, 0, 0}, "m"},       {"um", 1e-6, {1, 0, 0, 0}, "m"},
    {"kg", 1.0, {0, 1, 0, 0}, "kg"},       {"g", 1e-3, {0, 1, 0, 0}, "kg"},
    {"t", 1e3, {0, 1, 0, 0}, "kg"},        {"s", 1.0, {0, 0, 1, 0}, "s"},
    {"ms", 1e-3, {0, 0, 1, 0}, "s"},       {"min", 60.0, {0, 0, 1, 0}, "s"},
    {"h", 3600.0, {0, 0, 1, 0}, "s"},      {"N", 1.0, {1, 1, -2, 0}, "N"},
    {"mN", 1e-3, {1, 1, -2, 0}, "N"},      {"kN", 1e3, {1, 1, -2, 0}, "N"},
    {"MN", 1e6, {1, 1, -2, 0}, "N"},       {"Pa", 1.0, {-1, 1, -2, 0}, "Pa"},
    {"kPa", 1e3, {-1, 1, -2, 0}, "Pa"},    {"MPa", 1e6, {-1, 1, -2, 0}, "Pa"},
    {"GPa", 1e9, {-1, 1, -2, 0}, "Pa"},    {"bar", 1e5, {-1, 1, -2, 0}, "Pa"},
    {"J", 1.0, {2, 1, -2, 0}, "J"},        {"kJ", 1e3, {2, 1, -2, 0}, "J"},
    {"W", 1.0, {2, 1, -3, 0}, "W"},        {"kW", 1e3, {2, 1, -3, 0}, "W"},
    {"MW", 1e6, {2, 1, -3, 0}, "W"},       {"Hz", 1.0, {0, 0, -1, 0}, "Hz"},
    {"rad", 1.0, {0, 0, 0, 1}, "rad"},     {"deg", kDeg, {0, 0, 0, 1}, "rad"},
    {"°", kDeg, {0, 0, 0, 1}, "rad"},      {"rev", 2.0 * std::numbers::pi, {0, 0, 0, 1}, "rad"},
    {"rpm", 2.0 * std::numbers::pi / 60.0, {0, 0, -1, 1}, "rad/s"},
    {"1", 1.0, {0, 0, 0, 0}, "1"},         {"-", 1.0, {0, 0, 0, 0}, "1"},
};

const KnownUnit* Find(std::string_view name) {
  for (const KnownUnit& u : kUnits) {
    if (name == u.name) return &u;
  }
  return nullptr;
}

// Splits "m²" / "s^-2" / "m3"? into the unit name and its power. Only ², ³, ^N are powers.
bool SplitPower(std::string_view factor, std::string_view* name, int* power) {
  *power = 1;
  *name = factor;
  if (factor.ends_with("²")) {
    *power = 2;
    *name = factor.substr(0, factor.size() - std::string_view("²").size());
  } else if (factor.ends_with("³")) {
    *power = 3;
    *name = factor.substr(0, factor.size() - std::string_view("³").size());
  } else if (const std::size_t caret = factor.find('^'); caret != std::string_view::npos) {
    const std::string exponent(factor.substr(caret + 1));
    char* end = nullptr;
    const long p = std::strtol(exponent.c_str(), &end, 10);
    if (exponent.empty() || *end != '\0' || p == 0 || std::abs(p) > 6) return false;
    *power = static_cast<int>(p);
    *name = factor.substr(0, caret);
  }
  return !name->empty();
}

}  // namespace

const char* KnownUnits() {
  return "m mm cm km µm, kg g t, s ms min h, N mN kN MN, Pa kPa MPa GPa bar, J kJ, W kW MW, Hz, "
         "rad deg ° rev rpm, 1 (dimensionless), combined with · * / and powers ² ³ ^n "
         "(e.g. N·m/rad, kg·m², m/s^2)";
}

std::optional<Unit> ParseUnit(std::string_view text, std::string* why) {
  Unit out;
  bool divide = false;
  std::size_t i = 0;
  std::string si_num, si_den;
  bool any = false;
  while (i < text.size()) {
    // Separators: '·' (2 bytes in UTF-8), '*', '.', ' ', '/'.
    if (text.substr(i).starts_with("·")) { i += std::string_view("·").size(); continue; }
    const char ch = text[i];
    if (ch == '*' || ch == '.' || ch == ' ') { ++i; continue; }
    if (ch == '/') {
      if (divide) {
        *why = fmt::format("'{}' has two '/'; write one, e.g. N·s/(m) as N·s/m", text);
        return std::nullopt;
      }
      divide = true;
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && text[j] != '*' && text[j] != '.' && text[j] != ' ' &&
           text[j] != '/' && !text.substr(j).starts_with("·")) {
      ++j;
    }
    const std::string_view factor = text.substr(i, j - i);
    i = j;
    std::string_view name;
    int power = 1;
    const KnownUnit* u = SplitPower(factor, &name, &power) ? Find(name) : nullptr;
    if (u == nullptr) {
      *why = fmt::format("unknown unit '{}' in '{}'; known: {}", factor, text, KnownUnits());
      return std::nullopt;
    }
    any = true;
    const int sign = divide ? -1 : 1;
    out.to_si *= std::pow(u->to_si, sign * power);
    for (int k = 0; k < 4; ++k) out.dim[static_cast<std::size_t>(k)] += sign * power * u->dim[static_cast<std::size_t>(k)];
    std::string si = u->si;
    if (power != 1) si += power == 2 ? "²" : power == 3 ? "³" : fmt::format("^{}", power);
    std::string& part = divide ? si_den : si_num;
    if (si != "1") part += (part.empty() ? "" : "·") + si;
  }
  if (!any) {
    *why = "an empty unit; write an SI or lab unit (or leave `unit:` out for a plain number)";
    return std::nullopt;
  }
  out.si = (si_num.empty() ? "1" : si_num) + (si_den.empty() ? "" : "/" + si_den);
  return out;
}

std::optional<double> UnitSuffix(std::string_view name) {
  const KnownUnit* u = Find(name);
  if (u == nullptr || name == "1" || name == "-") return std::nullopt;
  return u->to_si;
}

}  // namespace hybridtest::modelfile
