// What an FMU substructure refuses, each a ConfigError that names the FMU file and the
// variable or capability: no binary for this platform, a missing variable, a wrong causality,
// a unit mismatch, state without get/set FMU state, FMI 1.0, not an FMU at all.
#include <gtest/gtest.h>

#include <string>

#include "fmi/fmi_test_support.h"
#include "hybridtest/common/error.h"
#include "hybridtest/fmi/model_description.h"

namespace hybridtest::fmi {
namespace {

using test::EditedFmu;
using test::FmuSpec;
using test::TestFmu;

// The message of the ConfigError that reading `yaml` throws ("" if none).
std::string Refusal(const std::string& yaml) {
  try {
    FmuSpec(yaml);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string Yaml(const std::string& fmu, const std::string& extra = "") {
  return "{type: fmu, fmu: " + fmu + ", displacement: x, force: F" + extra + "}";
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(FmuRefusal, MissingBinaryForThisPlatform) {
  const std::string fmu = EditedFmu("spring", "", "", "no_binary.fmu", false);
  const std::string e = Refusal(Yaml(fmu));
  EXPECT_HAS(e, "no_binary.fmu");
  EXPECT_HAS(e, "no binary for this platform (binaries/linux64/spring.so is missing)");
}

TEST(FmuRefusal, MissingVariableNamesTheKnownOnes) {
  const std::string e = Refusal("{type: fmu, fmu: " + TestFmu("spring") +
                                ", displacement: q1, force: F}");
  EXPECT_HAS(e, "spring.fmu: the FMU has no variable 'q1'; its inputs are: x");
  EXPECT_HAS(e, "test.yaml:1: substructures.r1.displacement");
}

TEST(FmuRefusal, WrongCausality) {
  const std::string e = Refusal("{type: fmu, fmu: " + TestFmu("spring") +
                                ", displacement: x, force: k}");
  EXPECT_HAS(e, "variable 'k' has causality parameter; a restoring force must be an output");
  const std::string p = Refusal(Yaml(TestFmu("spring"), ", parameters: {F: 3}"));
  EXPECT_HAS(p, "variable 'F' has causality output, not parameter; the FMU's parameters are: k");
}

// Issue 48: an FMI 3 array is refused at config time (not at the first fmi3SetFloat64),
// naming the variable and its dimensions; FMI 3 types are named as FMI 3 names them.
TEST(FmuRefusal, Fmi3ArraysAndTypesInFmi3Words) {
  const std::string array = EditedFmu("maxwell3", R"(unit="m"
        start="0"/>)", R"(unit="m" start="0 0 0"><Dimension start="3"/></Float64>)",
                                      "array3.fmu");
  const std::string e = Refusal(Yaml(array));
  EXPECT_HAS(e, "array3.fmu: variable 'x' is an array [3] (FMI 3 <Dimension>)");
  EXPECT_HAS(e, "test.yaml:1: substructures.r1.displacement");
  const std::string int32 = EditedFmu("maxwell3", R"(<Float64 name="F")", R"(<Int32 name="F")",
                                      "int3.fmu");
  EXPECT_HAS(Refusal(Yaml(int32)), "variable 'F' is of type Int32; a restoring force must be a "
                                   "Float64");
}

TEST(FmuRefusal, UnitMismatch) {
  const std::string seconds = EditedFmu("spring", R"(<Unit name="m"><BaseUnit m="1"/></Unit>)",
                                        R"(<Unit name="m"><BaseUnit s="1"/></Unit>)", "secs.fmu");
  EXPECT_HAS(Refusal(Yaml(seconds)), "secs.fmu: variable 'x' (a slot displacement) has unit "
                                     "'m', something else; expected a length (m) or an angle");
  const std::string moment = EditedFmu("spring", R"(<BaseUnit kg="1" m="1" s="-2"/>)",
                                       R"(<BaseUnit kg="1" m="2" s="-2"/>)", "moment.fmu");
  EXPECT_HAS(Refusal(Yaml(moment)), "displacement 'x' is a length (m) but force 'F' is a "
                                    "moment (N.m)");
  const std::string unknown = EditedFmu("spring", R"(<Real unit="m" start="0"/>)",
                                        R"(<Real unit="furlong" start="0"/>)", "furlong.fmu");
  EXPECT_HAS(Refusal(Yaml(unknown)), "variable 'x' has unit 'furlong', which hybridtest cannot "
                                     "check");
}

TEST(FmuRefusal, StateWithoutGetSetFmuState) {
  const std::string e = Refusal(Yaml(TestFmu("maxwell_nostate")));
  EXPECT_HAS(e, "maxwell_nostate.fmu: the FMU keeps a state (1 continuous state(s)) but does "
                "not declare canGetAndSetFMUstate");
  EXPECT_HAS(e, "roll the FMU back");
  // The same FMU with get/set is accepted (the refusal is about the capability alone).
  EXPECT_EQ(Refusal(Yaml(TestFmu("maxwell"))), "");
}

// A spring whose output does not declare its dependencies may hide a state: refused without
// get/set FMU state too.
TEST(FmuRefusal, UndeclaredDependenciesCountAsState) {
  const std::string fmu = EditedFmu("spring", R"(<Unknown index="2" dependencies="1"/>)",
                                    R"(<Unknown index="2"/>)", "undeclared.fmu");
  EXPECT_HAS(Refusal(Yaml(fmu)), "outputs that may depend on more than its inputs");
}

TEST(FmuRefusal, WrongVersionOrPlatformModelExchangeAndNotAnFmu) {
  // An FMI 3.0 description with only an FMI 2.0 binary folder: no binary for this platform.
  const std::string v3 = EditedFmu("spring", R"(fmiVersion="2.0")", R"(fmiVersion="3.0")",
                                   "v3.fmu");
  EXPECT_HAS(Refusal(Yaml(v3)), "v3.fmu: no binary for this platform "
                                "(binaries/x86_64-linux/spring.so is missing)");
  const std::string v1 = EditedFmu("spring", R"(fmiVersion="2.0")", R"(fmiVersion="1.0")",
                                   "v1.fmu");
  EXPECT_HAS(Refusal(Yaml(v1)), "v1.fmu: fmiVersion '1.0'; hybridtest imports FMI 2.0 and 3.0");
  const std::string me = EditedFmu("spring", "<CoSimulation", "<ModelExchange", "me.fmu");
  EXPECT_HAS(Refusal(Yaml(me)), "me.fmu: the FMU does not support co-simulation");
  const auto dir = test_support::FreshTempDir("fmi_not_zip");
  test_support::WriteText(dir / "plain.fmu", "not a zip");
  EXPECT_HAS(Refusal(Yaml((dir / "plain.fmu").string())), "plain.fmu: cannot open the FMU");
  EXPECT_HAS(Refusal(Yaml((dir / "absent.fmu").string())), "no FMU file at");
}

// Velocities are not passed (decision 0021): a `velocity:` key, or an unbound FMU input that is
// a velocity (which would silently stay at its start value), is refused, naming it.
TEST(FmuRefusal, VelocityInputsAreRefusedClearly) {
  EXPECT_HAS(Refusal(Yaml(TestFmu("spring"), ", velocity: v")),
             "velocity inputs are not passed to an FMU substructure");
  std::string xml = ReadMember(TestFmu("spring"), "modelDescription.xml");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"</UnitDefinitions>", R"(<Unit name="m/s"><BaseUnit m="1" s="-1"/></Unit></UnitDefinitions>)"},
           {"</ModelVariables>", R"(<ScalarVariable name="v" valueReference="7" causality="input"
               variability="continuous"><Real unit="m/s" start="0"/></ScalarVariable></ModelVariables>)"}}) {
    xml.replace(xml.find(from), from.size(), to);
  }
  const auto dir = test_support::FreshTempDir("fmi_velocity");
  const std::string fmu = (dir / "velocity.fmu").string();
  WriteArchive(fmu, {{"modelDescription.xml", xml},
                     {"binaries/linux64/spring.so",
                      ReadMember(TestFmu("spring"), "binaries/linux64/spring.so")}});
  const std::string e = Refusal(Yaml(fmu));
  EXPECT_HAS(e, "velocity.fmu: the FMU declares input 'v' in m/s, a velocity");
}

TEST(FmuRefusal, SlotCountMustMatch) {
  const YamlInput in = YamlInput::FromText(Yaml(TestFmu("spring")), "test.yaml");
  try {
    ParseFmuSubstructure(in, in.root(), "blade", {"r1", "r2"}, "substructures.blade", nullptr);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_HAS(std::string(e.what()), "expected 2 names of the FMU input (one per slot");
  }
}

TEST(ModelDescription, StateIsReadFromTheStructure) {
  const auto maxwell = ParseModelDescription(ReadMember(TestFmu("maxwell"), "modelDescription.xml"), "m");
  EXPECT_EQ(maxwell.num_states, 1);
  EXPECT_FALSE(maxwell.DeclaresNoState());
  EXPECT_TRUE(maxwell.can_get_and_set_state);
  EXPECT_EQ(maxwell.Find("der(y)")->value_reference, 6u);
  const auto spring = ParseModelDescription(ReadMember(TestFmu("spring"), "modelDescription.xml"), "s");
  EXPECT_TRUE(spring.DeclaresNoState());
  EXPECT_EQ(spring.UnitOf(*spring.Find("F"))->kg, 1);
  EXPECT_THROW(ParseModelDescription("<fmiModelDescription", "x"), ConfigError);
  // FMI 3.0: the state from ContinuousStateDerivative, dependencies by value reference.
  const auto v3 = ParseModelDescription(ReadMember(TestFmu("maxwell3"), "modelDescription.xml"), "3");
  EXPECT_TRUE(v3.is_fmi3());
  EXPECT_EQ(v3.num_states, 1);
  EXPECT_TRUE(v3.can_get_and_set_state);
  EXPECT_EQ(v3.guid, "{hybridtest-test-maxwell}");
  EXPECT_EQ(v3.Find("F")->type, "Float64");
  EXPECT_EQ(v3.output_dependencies.at(2), (std::vector<int>{1, 6}));
}

}  // namespace
}  // namespace hybridtest::fmi
