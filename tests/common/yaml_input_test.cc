#include "hybridtest/common/yaml_input.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"

namespace hybridtest {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The message of the ConfigError thrown by `f`, or "(no error)".
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

const char kRun[] =
    "model:\n"
    "  name: rotor\n"
    "integrator:\n"
    "  dt: abc\n"
    "  tableau: [1, 2]\n"
    "duration: -1\n";

TEST(YamlInput, FileErrorsNameFileLineKeyValueAndExpectation) {
  const YamlInput in = YamlInput::FromText(kRun, "run.yaml");
  const YAML::Node integ = in.Mapping(in.root(), "integrator", "integrator", true);
  EXPECT_EQ(ErrorOf([&] { in.Number(integ["dt"], "integrator.dt", "a time step in s"); }),
            "run.yaml:4: integrator.dt = 'abc': expected a time step in s");
  EXPECT_THAT(ErrorOf([&] { in.String(integ["tableau"], "integrator.tableau", "a name"); }),
              HasSubstr("run.yaml:5: integrator.tableau = '[1, 2]': expected a name"));
  EXPECT_THAT(ErrorOf([&] { in.PositiveNumber(in.root()["duration"], "duration", "> 0 s"); }),
              HasSubstr("run.yaml:6: duration = '-1': expected > 0 s"));
  EXPECT_EQ(in.Integer(YAML::Load("3"), "model.blades", "a whole number"), 3);
  EXPECT_THAT(ErrorOf([&] { in.Integer(YAML::Load("2.5"), "model.blades", "a whole number"); }),
              HasSubstr("model.blades = '2.5': expected a whole number"));
}

TEST(YamlInput, MissingKeysSayWhereToAddThem) {
  const YamlInput in = YamlInput::FromText(kRun, "run.yaml");
  EXPECT_EQ(ErrorOf([&] { in.ReadNumber(in.root()["model"], "model", "mass", "a mass in kg"); }),
            "run.yaml:2: model.mass: missing; expected a mass in kg; add `mass: ...` under model");
  EXPECT_THAT(ErrorOf([&] { in.Mapping(in.root(), "output", "output", true); }),
              HasSubstr("missing required section 'output:'"));
  EXPECT_FALSE(in.Mapping(in.root(), "output", "output", false).IsDefined());
  EXPECT_DOUBLE_EQ(in.ReadNumber(in.root()["model"], "model", "mass", "kg", 2.5), 2.5);
  EXPECT_EQ(in.ReadString(in.root()["model"], "model", "name", "x"), "rotor");
  EXPECT_EQ(in.ReadString(in.root()["model"], "model", "kind", "x"), "x");
}

TEST(YamlInput, UnknownKeysListTheAllowedOnes) {
  const YamlInput in = YamlInput::FromText(kRun, "run.yaml");
  EXPECT_THAT(ErrorOf([&] { in.CheckKeys(in.root(), "", {"model", "integrator"}); }),
              AllOf(HasSubstr("run.yaml:6: duration: unknown key 'duration'"),
                    HasSubstr("expected one of: model, integrator")));
  EXPECT_EQ(ErrorOf([&] { in.CheckKeys(in.root(), "", {"model", "integrator", "duration"}); }),
            "(no error)");
}

// Issue 50: `{description: rear contact x, in N}` cut the text at the comma and reported the
// rest as an unknown key without saying why.
TEST(YamlInput, AnUnknownKeyAfterACommaInsideBracesSuggestsQuotes) {
  const YamlInput in = YamlInput::FromText(
      "coordinates:\n  - {name: q1, description: rear contact x, in N}\n", "m.yaml");
  const YAML::Node item = in.root()["coordinates"][0];
  EXPECT_THAT(ErrorOf([&] { in.CheckKeys(item, "coordinates[0]", {"name", "description"}); }),
              AllOf(HasSubstr("unknown key 'in N'"), HasSubstr("put the whole text in quotes"),
                    HasSubstr("description: \"a, b\"")));
  // A block mapping's typo keeps the spelling hint.
  const YamlInput block = YamlInput::FromText("name: q1\ndescripton: x\n", "b.yaml");
  EXPECT_THAT(ErrorOf([&] { block.CheckKeys(block.root(), "", {"name", "description"}); }),
              AllOf(HasSubstr("check the spelling and the indentation"),
                    testing::Not(HasSubstr("quotes"))));
}

TEST(YamlInput, FragmentsAppendTheLineToTheCallersKeyPath) {
  const YAML::Node node = YAML::Load("a: 1\nb: soon\nc: [1, x]\n");
  const YamlInput in = YamlInput::ForNode(node);
  EXPECT_TRUE(in.path().empty());
  EXPECT_DOUBLE_EQ(in.ReadNumber(node, "f.yaml: bench", "a", "a number"), 1.0);
  EXPECT_EQ(ErrorOf([&] { in.ReadNumber(node, "f.yaml: bench", "b", "a delay in ms"); }),
            "f.yaml: bench.b (line 2) = 'soon': expected a delay in ms");
  EXPECT_THAT(ErrorOf([&] { in.Numbers(node["c"], "c", "numbers"); }),
              HasSubstr("c[1] (line 3) = 'x': expected numbers"));
  EXPECT_THAT(ErrorOf([&] { in.RequireMapping(node["a"], "f.yaml: bench.a"); }),
              HasSubstr("f.yaml: bench.a (line 1) = '1': expected a mapping"));
  EXPECT_THAT(ErrorOf([&] { in.ThrowValue(node["z"], "f.yaml: bench.z", "one of p, q"); }),
              HasSubstr("f.yaml: bench.z: missing; expected one of p, q"));
}

TEST(YamlInput, NonFiniteAndNonScalarNumbersAreRejected) {
  const YAML::Node node = YAML::Load("{a: .inf, b: .nan, c: {d: 1}, e: }");
  const YamlInput in = YamlInput::ForNode(node);
  for (const char* key : {"a", "b", "c"}) {
    EXPECT_THAT(ErrorOf([&] { in.ReadNumber(node, "", key, "a finite number"); }),
                HasSubstr("expected a finite number"))
        << key;
  }
  EXPECT_THAT(ErrorOf([&] { in.ReadNumber(node, "", "e", "a number", 1.0); }),
              HasSubstr("e (line 1): empty; expected a number; give `e:` a value"));
}

TEST(YamlInput, DocumentErrors) {
  EXPECT_THAT(ErrorOf([] { YamlInput::FromFile("/nonexistent/run.yaml"); }),
              HasSubstr("/nonexistent/run.yaml: cannot open"));
  EXPECT_THAT(ErrorOf([] { YamlInput::FromText("a: [1, 2\n", "bad.yaml"); }),
              AllOf(HasSubstr("bad.yaml:"), HasSubstr("not valid YAML")));
  EXPECT_THAT(ErrorOf([] { YamlInput::FromText("- 1\n- 2\n", "list.yaml", "keys such as x:"); }),
              HasSubstr("list.yaml: expected a YAML mapping at the top level (keys such as x:)"));
  const std::string path = ::testing::TempDir() + "/yaml_input_test.yaml";
  std::ofstream(path) << "x: 1\n";
  const YamlInput in = YamlInput::FromFile(path);
  EXPECT_EQ(in.text(), "x: 1\n");
  EXPECT_EQ(in.path(), path);
}

TEST(YamlInput, JoinKeyPath) {
  EXPECT_EQ(JoinKeyPath("", "dt"), "dt");
  EXPECT_EQ(JoinKeyPath("integrator", "dt"), "integrator.dt");
}

}  // namespace
}  // namespace hybridtest

namespace hybridtest {
namespace {

TEST(YamlInputGuards, DuplicateKeysAreRefusedWithBothLines) {
  const std::string text = "safety:\n  force_hard: 60\n  stroke_max: 0.1\n  force_hard: 10000\n";
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromText(text, "run.yaml"); }),
              AllOf(HasSubstr("run.yaml:4"), HasSubstr("'force_hard' appears twice"),
                    HasSubstr("lines 2 and 4")));
  // At the top level and inside a list of mappings too.
  EXPECT_THAT(ErrorOf([] { YamlInput::FromText("a: 1\nb: 2\na: 3\n", "t.yaml"); }),
              HasSubstr("lines 1 and 3"));
  EXPECT_THAT(ErrorOf([] { YamlInput::FromText("l:\n  - {x: 1, x: 2}\n", "t.yaml"); }),
              HasSubstr("'x' appears twice"));
  // The same key in two different mappings is fine.
  EXPECT_EQ(ErrorOf([] { YamlInput::FromText("a: {x: 1}\nb: {x: 2}\n", "t.yaml"); }),
            "(no error)");
}

TEST(YamlInputGuards, AliasBombsAreRefusedNotExpanded) {
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 9; ++i) {
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) text += std::string(k ? ", " : "") + "*a" + std::to_string(i - 1);
    text += "]\n";
  }
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromText(text, "bomb.yaml"); }),
              HasSubstr("YAML nodes once aliases"));
}

TEST(YamlInputGuards, OnlyRegularFilesAreRead) {
  const std::string dir = "/tmp/hybridtest_yaml_guard_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string fifo = dir + "/config.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A FIFO with no writer would block a plain open for ever: it is refused at once.
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromFile(fifo); }),
              AllOf(HasSubstr(fifo), HasSubstr("not a regular file (a FIFO)")));
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromFile(dir); }), HasSubstr("(a directory)"));
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromFile("/dev/zero"); }), HasSubstr("(a device)"));
  EXPECT_THAT(ErrorOf([&] { YamlInput::FromFile(dir + "/missing.yaml"); }),
              HasSubstr("cannot open this YAML file"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
