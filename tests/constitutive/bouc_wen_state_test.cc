// BoucWen::SaveState/RestoreState: a law restored from a saved committed state follows the same
// hysteresis as the original (bit for bit), and only the committed state is saved.
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/linear_spring.h"

namespace hybridtest::constitutive {
namespace {

TEST(BoucWenState, RestoredLawContinuesBitIdentically) {
  BoucWen original(BoucWen::FromYieldDisplacement(7200.0, 0.1, 0.01));
  for (double x : {0.004, 0.012, 0.02, 0.008}) {
    original.Trial(x);
    original.Commit();
  }
  original.Trial(-0.05);  // a trial is not committed: it must not be saved
  const auto saved = nlohmann::json::parse(original.SaveState().dump());
  BoucWen restored(BoucWen::FromYieldDisplacement(7200.0, 0.1, 0.01));
  restored.RestoreState(saved);
  EXPECT_EQ(restored.committed_displacement(), 0.008);
  for (double x : {-0.003, -0.015, 0.001, 0.017}) {
    EXPECT_EQ(restored.Trial(x), original.Trial(x)) << x;
    original.Commit();
    restored.Commit();
  }
  EXPECT_THROW(restored.RestoreState(nlohmann::json::object()), Error);
  EXPECT_EQ(LinearSpring(7200.0).SaveState(), nlohmann::json::object());  // elastic: no state
}

}  // namespace
}  // namespace hybridtest::constitutive
