#pragma once
// Builds a RestoringForceLaw from a YAML mapping. All values are SI.
//
//   type: linear       stiffness [N/m]
//   type: cantilever   length [m], width [m], thickness [m], youngs_modulus [Pa]
//                      (a linear spring with k = 3EI/L³, I = b t³/12; see cantilever.h)
//   type: bouc_wen     initial_stiffness [N/m], alpha [-], and EITHER
//                        yield_displacement [m] (optional n, default 1)
//                      OR A [-], beta [1/m^n], gamma [1/m^n], n [-];
//                      optional max_substep [m] (default z_u/200). See bouc_wen.h.
//
// Example:
//   specimen: {type: cantilever, length: 0.5, width: 0.1, thickness: 0.005, youngs_modulus: 210e9}
#include <memory>
#include <string_view>

#include <yaml-cpp/yaml.h>

#include "hybridtest/constitutive/restoring_force_law.h"

namespace hybridtest::constitutive {

// `where` is the key path of `node` for error messages, e.g. "bench.yaml: bench.specimen".
// Throws ConfigError naming the key path, the value given and the fix.
std::unique_ptr<RestoringForceLaw> ParseRestoringForceLaw(const YAML::Node& node,
                                                          std::string_view where);

}  // namespace hybridtest::constitutive
