// Figures of one run: valid, non-trivial images with the titles, labels and highlighting.
#include "hybridtest/report/plot.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/report/gnuplot_script.h"
#include "hybridtest/report/plot_layout.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

using testing::Slurp;

// Width and height from a PNG's IHDR chunk; {0, 0} when the signature or IHDR is wrong.
std::pair<std::uint32_t, std::uint32_t> PngSize(const std::string& bytes) {
  const std::string signature = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 24 || bytes.compare(0, 8, signature) != 0 ||
      bytes.compare(12, 4, "IHDR") != 0) {
    return {0, 0};
  }
  auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  return {be32(16), be32(20)};
}

std::string Find(const std::vector<std::string>& files, const std::string& name) {
  for (const std::string& f : files) {
    if (std::filesystem::path(f).filename() == name) return f;
  }
  return "";
}

TEST(WritePlots, RotorWithPhysicalBladeWritesFigure6LikeImages) {
  const testing::ScratchDir dir("plot-rotor");
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), {}));
  const auto files = WritePlots(run, dir / "fig");
  for (const char* name : {"displacements.png", "displacements.svg", "hub-speed.png",
                           "hub-speed.svg", "r1-command-position.png", "r1-command-position.svg",
                           "r1-force-displacement.png", "r1-force-displacement.svg",
                           "r1-force-time.png", "r1-lab-time.png", "restoring-forces.png"}) {
    SCOPED_TRACE(name);
    const std::string path = Find(files, name);
    ASSERT_FALSE(path.empty());
    const std::string bytes = Slurp(path);
    EXPECT_GT(bytes.size(), 5000u);
    if (path.ends_with(".png")) {
      const auto [w, h] = PngSize(bytes);
      EXPECT_EQ(w, 1000u);
      EXPECT_GT(h, 300u);
    } else {
      EXPECT_EQ(bytes.find("<?xml"), 0u);
      EXPECT_NE(bytes.find("<svg"), std::string::npos);
      EXPECT_NE(bytes.find("</svg>"), std::string::npos);
      if (path.find("force-displacement") == std::string::npos) {
        EXPECT_NE(bytes.find("time t [s]"), std::string::npos);
      }
    }
  }
  // Fig. 6a: title, units, and the physical blade in red with its own legend entry.
  const std::string svg = Slurp(Find(files, "displacements.svg"));
  EXPECT_NE(svg.find("Blade-tip displacements q1..q3 (run hybrid)"), std::string::npos);
  EXPECT_NE(svg.find("blade-tip displacement [m]"), std::string::npos);
  EXPECT_NE(svg.find("q1 (physical, r1)"), std::string::npos);
  EXPECT_NE(svg.find("rgb(214,  39,  40)"), std::string::npos);
  EXPECT_NE(svg.find(">q2<"), std::string::npos);
  // Fig. 6b: the hub speed u4 only.
  const std::string hub = Slurp(Find(files, "hub-speed.svg"));
  EXPECT_NE(hub.find("hub angular speed u4 [rad/s]"), std::string::npos);
  EXPECT_EQ(hub.find(">u1<"), std::string::npos);
  // Hysteresis: force against displacement, with units.
  const std::string loop = Slurp(Find(files, "r1-force-displacement.svg"));
  EXPECT_NE(loop.find("measured restoring force r1_force [N]"), std::string::npos);
  EXPECT_NE(loop.find("measured position r1_position [m]"), std::string::npos);
}

// Red only where the sidecar says a substructure is physical.
TEST(WritePlots, NoRedWhenEveryBladeIsNumerical) {
  const testing::ScratchDir dir("plot-numerical");
  testing::RotorRunSpec spec;
  spec.name = "numerical";
  spec.physical_r1 = false;
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), spec));
  const auto files = WritePlots(run, dir / "fig");
  const std::string svg = Slurp(Find(files, "displacements.svg"));
  EXPECT_NE(svg.find(">q1<"), std::string::npos);
  EXPECT_EQ(svg.find("physical"), std::string::npos);
  EXPECT_EQ(svg.find("rgb(214,  39,  40)"), std::string::npos);
  EXPECT_TRUE(Find(files, "r1-force-displacement.png").empty());
  EXPECT_TRUE(Find(files, "r1-limits.png").empty());
  EXPECT_EQ(files.size(), 6u);  // displacements, hub speed, restoring forces; PNG and SVG
}

TEST(MakeRunFigures, MarksEveryResumeOnTheTimeAxes) {
  const testing::ScratchDir dir("plot-resumed");
  testing::RotorRunSpec spec;
  spec.name = "resumed";
  io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), spec));
  run.metadata["resumes"] = nlohmann::json::array({{{"t", 0.125}, {"step", 125}}});
  const std::vector<PlotFigure> figures = MakeRunFigures(run);
  long time_panels = 0;
  for (const auto& figure : figures) {
    for (const auto& panel : figure.panels) {
      if (!panel.x_is_time) {
        EXPECT_TRUE(panel.marks.empty()) << figure.stem;  // force–displacement: no time axis
        continue;
      }
      ++time_panels;
      ASSERT_EQ(panel.marks.size(), 1u) << figure.stem;
      EXPECT_EQ(panel.marks[0].first, 0.125);
    }
  }
  EXPECT_GT(time_panels, 0);
  const std::string script = MakeGnuplotScript(figures, dir / "fig").text;
  EXPECT_NE(script.find("set arrow from 0.125, graph 0 to 0.125, graph 1"), std::string::npos);
  EXPECT_NE(script.find("\"resumed\""), std::string::npos);
}

TEST(WritePlots, WithoutSidecarDrawsPlainCoordinatesAndSpeeds) {
  const testing::ScratchDir dir("plot-plain");
  testing::RotorRunSpec spec;
  spec.sidecar = false;
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), spec));
  const auto files = WritePlots(run, dir / "fig");
  // The hub angle q4 grows far beyond the tip deflections: it gets its own figure.
  const std::string svg = Slurp(Find(files, "coordinates-q1-q3.svg"));
  ASSERT_FALSE(svg.empty());
  EXPECT_NE(svg.find("Generalized coordinates q1..q3 (run hybrid)"), std::string::npos);
  EXPECT_EQ(svg.find("physical"), std::string::npos);
  EXPECT_EQ(svg.find("rgb(214,  39,  40)"), std::string::npos);
  EXPECT_FALSE(Find(files, "coordinates-q4.png").empty());
  EXPECT_FALSE(Find(files, "speeds-u1-u3.png").empty());
  EXPECT_TRUE(Find(files, "hub-speed.png").empty());
}

TEST(WritePlots, LargeRunIsDecimatedButKeepsItsPeak) {
  const testing::ScratchDir dir("plot-large");
  testing::RotorRunSpec spec;
  spec.rows = 60001;
  spec.dt = 1e-4;
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), spec));
  const std::vector<PlotFigure> figures = MakeRunFigures(run);
  const GnuplotScript script = MakeGnuplotScript(figures, dir.path());
  // Every datablock holds at most kMaxPlotPoints lines.
  std::size_t longest = 0, current = 0;
  std::istringstream lines(script.text);
  for (std::string line; std::getline(lines, line);) {
    if (line.ends_with("<< EOD")) current = 0;
    else if (line == "EOD") longest = std::max(longest, current);
    else ++current;
  }
  EXPECT_LE(longest, static_cast<std::size_t>(kMaxPlotPoints));
  EXPECT_GT(longest, static_cast<std::size_t>(kMaxPlotPoints / 2));
  const auto files = RenderFigures(figures, dir / "fig");
  EXPECT_EQ(files.size(), 2 * figures.size());
  EXPECT_EQ(PngSize(Slurp(Find(files, "displacements.png"))).first, 1000u);
}

TEST(DefaultPlotDir, IsBesideTheRun) {
  EXPECT_EQ(DefaultPlotDir("results/hybrid.csv"), "results/hybrid-figures");
}

}  // namespace
}  // namespace hybridtest::report
