// The one name rule at the model-file boundary (issue 45 item 2, modelfile/names.h): every
// name a model file declares is checked where it is read, and one that could carry C, Python
// or LaTeX into generated text is refused at its file:line with the rule and a fix. Before
// the rule these files built (and check-model passed them).
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/modelfile/names.h"
#include "support/model_file_error.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

// Every kind of declared name, one per line.
constexpr char kAll[] =
    "name: p\n"                                                              // 1
    "parameters:\n"                                                          // 2
    "  l: {value: 1.0, unit: m}\n"                                           // 3
    "coordinates:\n"                                                         // 4
    "  - {name: th, unit: rad}\n"                                            // 5
    "speeds:\n"                                                              // 6
    "  - {name: w, unit: rad/s}\n"                                           // 7
    "tables:\n"                                                              // 8
    "  tab: {x: [0, 1], y: [0, 1]}\n"                                        // 9
    "time_functions:\n"                                                      // 10
    "  ramp: \"2 * l\"\n"                                                    // 11
    "frames:\n"                                                              // 12
    "  - {name: A, parent: N, axis: z, angle: th}\n"                         // 13
    "points:\n"                                                              // 14
    "  - {name: P, from: O, frame: A, position: [l, 0, 0]}\n"                // 15
    "particles:\n"                                                           // 16
    "  - {name: bob, point: P, mass: 2}\n"                                   // 17
    "bodies:\n"                                                              // 18
    "  - {name: rod, frame: A, mass_center: P, mass: 1, inertia: [1, 1, 1]}\n"  // 19
    "slots:\n"                                                               // 20
    "  - {name: r1, unit: N·m, displacement: th, stiffness: 1}\n"            // 21
    "states:\n"                                                              // 22
    "  z1: {rate: \"-w * z1\", initial: 0, unit: \"1\"}\n"                   // 23
    "forces:\n"                                                              // 24
    "  - {name: push on bob, point: P, value: [0, 0, 0]}\n"                  // 25
    "torques:\n"                                                             // 26
    "  - {name: spring, frame: A, value: [0, 0, -r1]}\n";                    // 27

std::string ErrorOf(const std::string& text) { return ::test_support::ModelFileError(text); }

// kAll with `from` (once, on its line) replaced by `to`.
std::string With(const std::string& from, const std::string& to) {
  std::string s = kAll;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  s.replace(at, from.size(), to);
  return s;
}

TEST(ModelFileNamesTest, TheRule) {
  for (const char* ok : {"q1", "theta_dot", "blade1.k_b", "_x", "L", "u1_dot", "import_"}) {
    EXPECT_EQ(NameProblem(ok), "") << ok;
  }
  EXPECT_EQ(NameProblem("turbine-damper", NameKind::kLabel), "");
  EXPECT_EQ(NameProblem("gravity on bob 1", NameKind::kText), "");
  EXPECT_THAT(NameProblem("turbine-damper"), HasSubstr("'-'"));
  EXPECT_THAT(NameProblem("1q"), HasSubstr("starts with a digit"));
  EXPECT_THAT(NameProblem("import"), HasSubstr("keyword of Python"));
  EXPECT_THAT(NameProblem("class"), HasSubstr("keyword of C, C++ or Python"));
  EXPECT_THAT(NameProblem("a.while"), HasSubstr("'while' is a keyword"));
  EXPECT_THAT(NameProblem("__import__"), HasSubstr("reserved"));
  EXPECT_THAT(NameProblem("_Bool"), HasSubstr("reserved"));
  EXPECT_THAT(NameProblem("a..b"), HasSubstr("empty part"));
  EXPECT_THAT(NameProblem("a\nb"), HasSubstr("control character \\x0a"));
  EXPECT_THAT(NameProblem("\xce\xb8"), HasSubstr("not ASCII"));
  EXPECT_THAT(NameProblem(std::string(kMaxNameLength + 1, 'a')), HasSubstr("at most 64"));
  EXPECT_EQ(NameProblem(std::string(kMaxNameLength, 'a')), "");
  EXPECT_THAT(NameProblem("bob\"; x", NameKind::kText), HasSubstr("'\"'"));
  EXPECT_THAT(NameProblem("a */ b", NameKind::kText), HasSubstr("'*'"));
  EXPECT_EQ(LabelFromStem("2-link pendulum"), "_2-link_pendulum");
  EXPECT_EQ(LabelFromStem("import"), "import_");
}

TEST(ModelFileNamesTest, AValidFileWithEveryKindOfNameBuilds) {
  EXPECT_EQ(ErrorOf(kAll), "no error");
  EXPECT_EQ(ErrorOf(With("name: p", "name: turbine-damper")), "no error");
  EXPECT_EQ(ErrorOf(With("  l: {", "  blade1.k_b: 1\n  l: {")), "no error");
}

TEST(ModelFileNamesTest, CPythonAndLatexInNamesAreRefusedAtTheirLine) {
  struct Case {
    std::string from, to, where;
  };
  const std::vector<Case> cases = {
      // LaTeX in the model's name (\input includes a file into the document).
      {"name: p", "name: '\\input{/etc/passwd}'", "m.yaml:1: name"},
      // Python in a parameter (the SymPy module would run it).
      {"  l: {", "  \"l') or __import__('os').system('id') #\": 1\n  l: {",
       "m.yaml:3: parameters.l') or"},
      // C in a coordinate (it closes the generated comment).
      {"name: th,", "name: 'th */ int evil; /*',", "m.yaml:5: coordinates[0].name"},
      {"name: w,", "name: \"w\\nimport os\",", "m.yaml:7: speeds[0].name"},
      {"  tab: {", "  'tab{x}': {", "m.yaml:9: tables.tab{x}"},
      {"  ramp: ", "  __import__: ", "m.yaml:11: time_functions.__import__"},
      {"name: A,", "name: class,", "m.yaml:13: frames[0].name"},
      {"name: P,", "name: 1P,", "m.yaml:15: points[0].name"},
      {"name: bob,", "name: 'bob\"); evil(',", "m.yaml:17: particles[0].name"},
      {"name: rod,", "name: 'rod \\input{x}',", "m.yaml:19: bodies[0].name"},
      {"name: r1,", "name: r1.,", "m.yaml:21: slots[0].name"},
      {"  z1: {", "  lambda: {", "m.yaml:23: states.lambda"},
      {"name: push on bob,", "name: 'push */ on',", "m.yaml:25: forces[0].name"},
      {"name: spring,", "name: \"spring\\n\",", "m.yaml:27: torques[0].name"},
      {"name: th,", "name: " + std::string(65, 't') + ",", "m.yaml:5: coordinates[0].name"},
  };
  for (const Case& c : cases) {
    EXPECT_THAT(ErrorOf(With(c.from, c.to)),
                AllOf(HasSubstr(c.where), HasSubstr("not a valid name"), HasSubstr("rename it")))
        << c.to;
  }
  // The fix is spelled out: the rule and a name that follows it.
  EXPECT_THAT(ErrorOf(With("name: A,", "name: class,")),
              AllOf(HasSubstr("'class' is a keyword of C, C++ or Python"),
                    HasSubstr("ASCII letters, digits and '_'"), HasSubstr("e.g. to 'class_'")));
  // A control character is shown escaped, never raw.
  const std::string newline = ErrorOf(With("name: w,", "name: \"w\\nimport os\","));
  EXPECT_THAT(newline, HasSubstr("'w\\x0Aimport os'"));
  EXPECT_EQ(newline.find('\n'), std::string::npos) << newline;
}

// kAll with `section` appended (after the torques, line 27), its LABEL replaced by `label`.
std::string WithSection(const std::string& section, const std::string& label) {
  std::string s = With("name: spring, frame: A, value: [0, 0, -r1]}\n",
                       fmt::format("name: spring, frame: A, value: [0, 0, -r1]}}\n{}", section));
  s.replace(s.find("LABEL"), 5, label);
  return s;
}

// Constraint names and modes' labels are text (spaces allowed), by the same rule: a label is
// printed by `modes` and kept in its JSON.
TEST(ModelFileNamesTest, ConstraintNamesAndModeLabelsAreText) {
  const std::string constraint = "constraints:\n  - {name: LABEL, holonomic: \"th - 0\"}\n";
  const std::string mode = "modes:\n  labels:\n    - {name: LABEL}\n";
  // (This one-speed model cannot take a constraint; the name itself passes the rule.)
  EXPECT_THAT(ErrorOf(WithSection(constraint, "closing loop")),
              Not(HasSubstr("not a valid name")));
  EXPECT_EQ(ErrorOf(WithSection(mode, "first swing")), "no error");
  EXPECT_THAT(ErrorOf(WithSection(constraint, "'c\\input{x}'")),
              AllOf(HasSubstr("m.yaml:29: constraints[0].name"), HasSubstr("not a valid name")));
  EXPECT_THAT(ErrorOf(WithSection(mode, "'weave \\input{x}'")),
              AllOf(HasSubstr("m.yaml:30: modes.labels[0].name"), HasSubstr("not a valid name")));
}

}  // namespace
}  // namespace hybridtest::modelfile
