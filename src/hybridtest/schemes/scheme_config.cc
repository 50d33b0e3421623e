// See scheme_config.h.
#include "hybridtest/schemes/scheme_config.h"

#include "hybridtest/common/error.h"
#include "hybridtest/schemes/alpha_os.h"
#include "hybridtest/schemes/mr_os.h"
#include "hybridtest/schemes/runge_kutta_scheme.h"

namespace hybridtest::schemes {

std::string SchemeKindName(SchemeKind kind) {
  switch (kind) {
    case SchemeKind::kRungeKutta: return "runge-kutta";
    case SchemeKind::kAlphaOs: return "alpha-os";
    case SchemeKind::kMrOs: return "mr-os";
  }
  return "?";
}

std::unique_ptr<HybridScheme> MakeScheme(const SchemeConfig& config,
                                         const integrators::ButcherTableau& tableau, double dt,
                                         double duration, long steps,
                                         const multibody::Model& model, const SlotInfo& slots) {
  switch (config.kind) {
    case SchemeKind::kRungeKutta:
      return std::make_unique<RungeKuttaScheme>(model, tableau, dt, steps);
    case SchemeKind::kAlphaOs:
      return std::make_unique<AlphaOs>(model, config, slots, dt, duration, steps);
    case SchemeKind::kMrOs:
      return std::make_unique<MrOs>(model, config, slots, dt, duration, steps);
  }
  throw ConfigError("unknown integrator.scheme");
}

}  // namespace hybridtest::schemes
