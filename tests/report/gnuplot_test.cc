// Running gnuplot: clear errors when it is missing or fails; scripts quote text safely.
#include "hybridtest/report/gnuplot.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

// The message of the IoError fn throws, or "" if it throws none.
template <typename Fn>
std::string IoErrorOf(Fn fn) {
  try {
    fn();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(RunGnuplot, MissingProgramSaysToInstallGnuplotNox) {
  const std::string message =
      IoErrorOf([] { RunGnuplot("print 1\n", "/nonexistent/hybridtest-no-gnuplot"); });
  EXPECT_NE(message.find("install gnuplot-nox"), std::string::npos) << message;
  EXPECT_NE(message.find("/nonexistent/hybridtest-no-gnuplot"), std::string::npos) << message;
}

TEST(RunGnuplot, FailureIncludesGnuplotsStderr) {
  const std::string message = IoErrorOf([] { RunGnuplot("set nonsense_option_xyz\n"); });
  EXPECT_NE(message.find("exited with status"), std::string::npos) << message;
  EXPECT_NE(message.find("nonsense_option_xyz"), std::string::npos) << message;
}

TEST(RunGnuplot, ValidScriptSucceeds) { EXPECT_NO_THROW(RunGnuplot("x = 1\n")); }

TEST(QuoteGnuplot, EscapesQuotesAndBackslashesAndFlattensLines) {
  EXPECT_EQ(QuoteGnuplot("a\"b\\c\nd"), "\"a\\\"b\\\\c d\"");
}

TEST(RenderFigures, HostileLabelsAreDrawnLiterally) {
  const testing::ScratchDir dir("gnuplot-labels");
  PlotSeries series{"r1_force \"quoted\" \\ @", Eigen::VectorXd::LinSpaced(5, 0, 1),
                    Eigen::VectorXd::LinSpaced(5, 1, 2)};
  PlotFigure figure{"odd", "Title with \"quotes\" and r1_force", {{"p", "x [m]", "y [N]", true,
                                                                  {series}, {}}}};
  const auto files = RenderFigures({figure}, dir.path());
  ASSERT_EQ(files.size(), 2u);
  const std::string svg = testing::Slurp(files[1]);
  EXPECT_NE(svg.find("r1_force"), std::string::npos);  // noenhanced: no subscript
  EXPECT_NE(svg.find("y [N]"), std::string::npos);
}

TEST(RenderFigures, UnwritableDirectoryIsAnIoError) {
  EXPECT_THROW(RenderFigures({}, "/proc/hybridtest-cannot-create/figs"), IoError);
}

}  // namespace
}  // namespace hybridtest::report
