#pragma once
// Units of a slot's FMU variables (FMI 2.0 section 2.2.2, UnitDefinitions): the displacement
// input must be a length (or an angle, for a rotational slot) and the force output a force (or
// a moment), where the FMU declares units. A unit with a BaseUnit is checked by its SI
// exponents and converted by its factor and offset (SI = factor · value + offset); a unit
// without one is accepted only by a well-known name (m, mm, rad, N, kN, N.m, ...). A variable
// without a unit is taken as SI.
#include <string>

#include "hybridtest/fmi/model_description.h"

namespace hybridtest::fmi {

struct UnitCheck {
  double in_factor = 1.0, in_offset = 0.0;    // displacement: SI = factor · fmu + offset
  double out_factor = 1.0, out_offset = 0.0;  // force: SI = factor · fmu + offset
};

// Throws ConfigError naming `fmu`, the variable, its unit and what was expected.
UnitCheck CheckSlotUnits(const ModelDescription& md, const ModelVariable& displacement,
                         const ModelVariable& force, const std::string& fmu);

}  // namespace hybridtest::fmi
