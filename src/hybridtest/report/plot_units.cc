#include "hybridtest/report/plot_units.h"

#include <map>

#include "hybridtest/common/error.h"

namespace hybridtest::report {
namespace {

// Metres per display length unit and newtons per display force unit.
const std::map<std::string, double>& LengthUnits() {
  static const std::map<std::string, double> units{
      {"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"\u00b5m", 1e-6}};
  return units;
}

const std::map<std::string, double>& ForceUnits() {
  static const std::map<std::string, double> units{{"N", 1.0}, {"kN", 1e3}, {"MN", 1e6}};
  return units;
}

bool IsMoment(const std::string& unit) {
  return unit == "N\u00b7m" || unit == "N*m" || unit == "N.m" || unit == "Nm";
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

[[noreturn]] void ThrowToken(const std::string& spec, const std::string& token) {
  throw ConfigError("--units " + spec + ": '" + token +
                    "' is not a unit; expected comma-separated lengths (m, cm, mm, um) and "
                    "forces (N, kN, MN), or length=UNIT / force=UNIT, e.g. --units mm,kN");
}

}  // namespace

double PlotUnits::Factor(const std::string& u) const {
  const double l = LengthUnits().at(length), f = ForceUnits().at(force);
  if (u == "m" || u == "m/s" || u == "m/s^2" || u == "m/s\u00b2") return 1.0 / l;
  if (u == "N") return 1.0 / f;
  if (IsMoment(u)) return 1.0 / f;
  if (u == "N/m") return l / f;
  return 1.0;
}

std::string PlotUnits::Label(const std::string& u) const {
  if (u == "m") return length;
  if (u == "m/s") return length + "/s";
  if (u == "m/s^2" || u == "m/s\u00b2") return length + u.substr(1);
  if (u == "N") return force;
  if (IsMoment(u)) return force + "\u00b7m";
  if (u == "N/m") return force + "/" + length;
  return u;
}

PlotUnits ParsePlotUnits(const std::string& spec) {
  PlotUnits units;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = spec.find(',', start);
    const std::string token =
        Trim(spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    start = comma == std::string::npos ? spec.size() + 1 : comma + 1;
    if (token.empty()) continue;
    std::string quantity, unit = token;
    if (const auto eq = token.find('='); eq != std::string::npos) {
      quantity = Trim(token.substr(0, eq));
      unit = Trim(token.substr(eq + 1));
      if (quantity != "length" && quantity != "force") ThrowToken(spec, token);
    }
    const bool is_length = LengthUnits().count(unit) > 0;
    const bool is_force = ForceUnits().count(unit) > 0;
    if ((quantity == "length" || quantity.empty()) && is_length) {
      units.length = unit == "\u00b5m" ? "um" : unit;
    } else if ((quantity == "force" || quantity.empty()) && is_force) {
      units.force = unit;
    } else {
      ThrowToken(spec, token);
    }
  }
  return units;
}

}  // namespace hybridtest::report
