// See fmu_units.h.
#include "hybridtest/fmi/fmu_units.h"

#include <fmt/core.h>

#include <array>
#include <optional>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

enum class Dimension { kLength, kAngle, kForce, kMoment, kOther };

const char* Name(Dimension d) {
  switch (d) {
    case Dimension::kLength: return "a length (m)";
    case Dimension::kAngle: return "an angle (rad)";
    case Dimension::kForce: return "a force (N)";
    case Dimension::kMoment: return "a moment (N.m)";
    case Dimension::kOther: return "something else";
  }
  return "?";
}

Dimension Of(const UnitDefinition& u) {
  const bool rest = u.a == 0 && u.k == 0 && u.mol == 0 && u.cd == 0;
  if (!rest) return Dimension::kOther;
  if (u.kg == 0 && u.m == 1 && u.s == 0 && u.rad == 0) return Dimension::kLength;
  if (u.kg == 0 && u.m == 0 && u.s == 0 && u.rad == 1) return Dimension::kAngle;
  if (u.kg == 1 && u.m == 1 && u.s == -2 && u.rad == 0) return Dimension::kForce;
  if (u.kg == 1 && u.m == 2 && u.s == -2 && (u.rad == 0 || u.rad == -1)) return Dimension::kMoment;
  return Dimension::kOther;
}

// Units known by name alone (a unit declared without a BaseUnit).
std::optional<UnitDefinition> ByName(const std::string& name) {
  struct Known {
    const char* name;
    int kg, m, s, rad;
    double factor;
  };
  static const std::array<Known, 12> known{{{"m", 0, 1, 0, 0, 1.0},
                                            {"mm", 0, 1, 0, 0, 1e-3},
                                            {"cm", 0, 1, 0, 0, 1e-2},
                                            {"rad", 0, 0, 0, 1, 1.0},
                                            {"deg", 0, 0, 0, 1, 0.017453292519943295},
                                            {"N", 1, 1, -2, 0, 1.0},
                                            {"kN", 1, 1, -2, 0, 1e3},
                                            {"N.m", 1, 2, -2, 0, 1.0},
                                            {"N*m", 1, 2, -2, 0, 1.0},
                                            {"Nm", 1, 2, -2, 0, 1.0},
                                            {"N·m", 1, 2, -2, 0, 1.0},
                                            {"kN.m", 1, 2, -2, 0, 1e3}}};
  for (const auto& k : known) {
    if (name != k.name) continue;
    UnitDefinition u;
    u.name = name;
    u.has_base_unit = true;
    u.kg = k.kg;
    u.m = k.m;
    u.s = k.s;
    u.rad = k.rad;
    u.factor = k.factor;
    return u;
  }
  return std::nullopt;
}

// The definition of v's unit (nullopt: none declared, SI taken). Throws for one that cannot
// be checked.
std::optional<UnitDefinition> Resolve(const ModelDescription& md, const ModelVariable& v,
                                      const std::string& fmu) {
  if (v.unit.empty()) return std::nullopt;
  const UnitDefinition* def = md.UnitOf(v);
  if (def != nullptr && def->has_base_unit) return *def;
  if (auto known = ByName(v.unit)) return known;
  throw ConfigError(fmt::format("{}: variable '{}' has unit '{}', which hybridtest cannot "
                                "check: declare it in the FMU's UnitDefinitions with a "
                                "BaseUnit (SI exponents, factor, offset)", fmu, v.name, v.unit));
}

}  // namespace

UnitCheck CheckSlotUnits(const ModelDescription& md, const ModelVariable& displacement,
                         const ModelVariable& force, const std::string& fmu) {
  UnitCheck out;
  const auto du = Resolve(md, displacement, fmu);
  const auto fu = Resolve(md, force, fmu);
  std::optional<Dimension> dd, fd;
  if (du) {
    dd = Of(*du);
    if (dd != Dimension::kLength && dd != Dimension::kAngle) {
      throw ConfigError(fmt::format("{}: variable '{}' (a slot displacement) has unit '{}', "
                                    "{}; expected a length (m) or an angle (rad)",
                                    fmu, displacement.name, du->name, Name(*dd)));
    }
    out.in_factor = du->factor;
    out.in_offset = du->offset;
  }
  if (fu) {
    fd = Of(*fu);
    if (fd != Dimension::kForce && fd != Dimension::kMoment) {
      throw ConfigError(fmt::format("{}: variable '{}' (a restoring force) has unit '{}', {}; "
                                    "expected a force (N) or a moment (N.m)",
                                    fmu, force.name, fu->name, Name(*fd)));
    }
    out.out_factor = fu->factor;
    out.out_offset = fu->offset;
  }
  if (dd && fd && ((*dd == Dimension::kLength) != (*fd == Dimension::kForce))) {
    throw ConfigError(fmt::format("{}: displacement '{}' is {} but force '{}' is {}: a "
                                  "translational slot pairs m with N, a rotational one rad with "
                                  "N.m", fmu, displacement.name, Name(*dd), force.name,
                                  Name(*fd)));
  }
  return out;
}

}  // namespace hybridtest::fmi
