// Every generator escapes what it writes (issue 45 item 2, defence in depth behind the model
// file's name rule): a model built in C++ (so past the model-file rule) whose names carry C,
// Python and LaTeX still gives C whose only comment ends where hybridtest ends it, a Python
// module whose only statements are hybridtest's, and LaTeX that includes nothing.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/compiled_model.h"
#include "hybridtest/symbolic/equations.h"
#include "hybridtest/symbolic/print_expression.h"
#include "hybridtest/symbolic/write_equations.h"

namespace hybridtest::symbolic {
namespace {

using multibody::ScalarField;

const std::string kC = "q */ int evil; /* \"x\\\n#include <stdlib.h>";
const std::string kPython = "p'); __import__('os').system('id'); ('\n\"\"\"import os #";
const std::string kLatex = "B\\input{/etc/passwd}$x$";

multibody::Model Hostile() {
  multibody::ModelBuilder b({{kC, "rad", "a coordinate"}}, {{kPython, "rad/s", "its speed"}});
  const auto A = b.AddFrameAboutAxis(kLatex, b.newtonian(), {0, 0, 1}, ScalarField::Coordinate(0));
  const auto P = b.AddPoint(kPython, b.origin(), A,
                            {ScalarField::Constant(0.5), ScalarField::Constant(0.0), {}});
  b.AddParticle("bob", P, 2.0);
  b.AddRestoringForceSlot(kC + "r", "slot", ScalarField::Coordinate(0), "N");
  b.AddForce("spring", P, A, [](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return multibody::Vector3<T>(T(0.0), -a.r[0], T(0.0));
  });
  return std::move(b).Build();
}

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(GeneratedText, CKeepsNamesInsideItsCommentAndString) {
  const multibody::Model model = Hostile();
  const std::string c = WriteC(model, DeriveRhs(model), kC, kCompiledFunction).source;
  EXPECT_EQ(Count(c, "*/"), 1) << c;       // the header's own end only
  EXPECT_EQ(Count(c, "#include"), 1) << c;  // <math.h> only
  std::istringstream lines(c);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("_model[]") != std::string::npos) {
      EXPECT_EQ(Count(line, "\""), 2) << line;
    }
  }
  EXPECT_THROW(WriteC(model, DeriveRhs(model), "m", "f(); int x"), ModelError);
}

TEST(GeneratedText, PythonHasOnlyItsOwnStatements) {
  const multibody::Model model = Hostile();
  DocumentInfo info{kPython, "d", kPython + ".yaml", {{kPython, 1.0, "m\nimport os", "p"}}, false};
  const std::string py = WriteEquations(model, DeriveEquations(model), info, Format::kSympy);
  std::istringstream lines(py);
  int imports = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("import", 0) == 0) {
      ++imports;
      EXPECT_EQ(line, "import sympy as sp");
    }
  }
  EXPECT_EQ(imports, 1) << py;
  EXPECT_EQ(Count(py, "\"\"\""), 2) << py;  // the docstring's own quotes
  EXPECT_EQ(py.find("('os')"), std::string::npos) << py;  // only escaped: (\'os\')
  EXPECT_NE(py.find("__import__(\\'os\\')"), std::string::npos) << py;
  EXPECT_EQ(PythonString("a'b\\c\n"), "'a\\'b\\\\c\\x0a'");
}

TEST(GeneratedText, LatexIncludesNothing) {
  const multibody::Model model = Hostile();
  DocumentInfo info{kLatex, kLatex, kLatex, {}, false};
  const std::string tex = WriteEquations(model, DeriveEquations(model), info, Format::kLatex);
  EXPECT_EQ(tex.find("\\input"), std::string::npos) << tex;
  EXPECT_NE(tex.find("\\textbackslash{}input\\{/etc/passwd\\}\\$x\\$"), std::string::npos) << tex;
  EXPECT_EQ(LatexText("a_b{c}\\d$e^f~g%h&i#j"),
            "a\\_b\\{c\\}\\textbackslash{}d\\$e\\textasciicircum{}f\\textasciitilde{}g\\%h\\&i\\#j");
}

}  // namespace
}  // namespace hybridtest::symbolic
