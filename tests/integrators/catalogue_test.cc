// The catalogue: exactly the seven documented methods, each valid, each with the stage count and
// order its header comment states; FindTableau finds them and helps with typos.
#include "hybridtest/integrators/catalogue.h"

#include <set>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::integrators {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(Catalogue, HasExactlyTheDocumentedMethods) {
  EXPECT_THAT(TableauNames(),
              ElementsAre("euler", "heun", "midpoint", "ralston", "rk3", "rk4", "rk38"));
  EXPECT_EQ(Catalogue().size(), 7u);
}

TEST(Catalogue, NamesAreUniqueAndTitlesGiven) {
  std::set<std::string> names;
  for (const auto& t : Catalogue()) {
    EXPECT_TRUE(names.insert(t.name).second) << "duplicate name " << t.name;
    EXPECT_FALSE(t.title.empty()) << t.name;
  }
}

TEST(Catalogue, EveryTableauValidates) {
  for (const auto& t : Catalogue()) {
    EXPECT_NO_THROW(ValidateTableau(t, "catalogue")) << t.name;
  }
}

TEST(Catalogue, StagesAndOrdersMatchTheHeaderComment) {
  struct Expected {
    const char* name;
    int stages;
    int order;
  };
  const std::vector<Expected> expected = {{"euler", 1, 1}, {"heun", 2, 2}, {"midpoint", 2, 2},
                                          {"ralston", 2, 2}, {"rk3", 3, 3}, {"rk4", 4, 4},
                                          {"rk38", 4, 4}};
  for (const auto& e : expected) {
    const ButcherTableau& t = FindTableau(e.name);
    EXPECT_EQ(t.name, e.name);
    EXPECT_EQ(t.stages(), e.stages) << e.name;
    EXPECT_EQ(t.order, e.order) << e.name;
  }
}

TEST(Catalogue, FindReturnsTheCatalogueEntry) {
  for (const auto& t : Catalogue()) EXPECT_EQ(&FindTableau(t.name), &t);
}

std::string FindMessage(std::string_view name) {
  try {
    FindTableau(name);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "FindTableau found '" << name << "'";
  return "";
}

TEST(Catalogue, UnknownNameListsKnownNamesAndSuggestsClosest) {
  const std::string message = FindMessage("huen");
  EXPECT_THAT(message, AllOf(HasSubstr("'huen'"), HasSubstr("did you mean 'heun'")));
  for (const auto& name : TableauNames()) EXPECT_THAT(message, HasSubstr(name));

  EXPECT_THAT(FindMessage("RK4"), HasSubstr("did you mean 'rk4'"));
  EXPECT_THAT(FindMessage("rk_38"), HasSubstr("did you mean 'rk38'"));
  EXPECT_THAT(FindMessage("midpt"), HasSubstr("did you mean 'midpoint'"));
}

}  // namespace
}  // namespace hybridtest::integrators
