#pragma once
// Units of a model file: every unit written (parameters, coordinates, speeds, `30 deg` in an
// expression) is parsed into a factor to SI and a dimension, or refused. Nothing is guessed:
// `L: {value: 600, unit: mm}` is 0.6 m inside; an unknown unit is an error naming it.
//
// A unit is a product of factors separated by `·`, `*`, `.` or a space, with `/` dividing
// everything after it (`N·m·s/rad`, `kg·m²`, `m/s^2`, `1/s`). A factor is a known unit with an
// optional power (`²`, `³`, `^2`, `^-1`). Known: m mm cm km µm um, kg g t, s ms min h, N kN MN
// mN, Pa kPa MPa GPa bar, J kJ, W kW MW, Hz, rad deg ° rev rpm, 1 and - (dimensionless).
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace hybridtest::modelfile {

struct Unit {
  double to_si = 1.0;               // SI value = given value × to_si
  std::array<int, 4> dim{0, 0, 0, 0};  // exponents of m, kg, s, rad
  std::string si;                   // the SI unit written the same way ("kN/mm" → "N/m")
};

// The unit `text`, or nullopt with the reason in `why` (the unknown factor and the known ones).
std::optional<Unit> ParseUnit(std::string_view text, std::string* why);

// The factor to SI of a unit that may follow a number in an expression (`30 deg`, `600 mm`),
// or nullopt if `name` is not a single known unit.
std::optional<double> UnitSuffix(std::string_view name);

// A short list of the known units, for messages.
const char* KnownUnits();

}  // namespace hybridtest::modelfile
