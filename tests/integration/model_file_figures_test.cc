// Figures and reports of a model-file run through the real binary: `hybridtest plot` on the
// run of examples/04_wind_turbine/dummy.yaml draws every coordinate (each in a figure of its
// group, named from the model), every slot's restoring force and speed; `report` leads with
// the summary; `eom` labels the N·m slots with their unit; bad --units is exit 2.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::pair<int, std::string> Hybridtest(const std::string& args) {
  return testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " " + args, 300);
}

// The wind turbine's dummy run, made once per test process.
fs::path TurbineRun() {
  static const fs::path csv = [] {
    const fs::path dir = test_support::FreshTempDir("model_file_figures");
    const fs::path out = dir / "wind_turbine_dummy.csv";
    const auto [status, text] = Hybridtest(fmt::format(
        "run {}/examples/04_wind_turbine/dummy.yaml --out {} --quiet", kSource, out.string()));
    EXPECT_EQ(status, 0) << text;
    return out;
  }();
  return csv;
}

TEST(ModelFileFigures, PlotDrawsEveryCoordinateGroupNamedFromTheModel) {
  const fs::path csv = TurbineRun();
  const fs::path figures = csv.parent_path() / "figures";
  const auto [status, out] = Hybridtest(fmt::format("plot {} --out {}", csv.string(),
                                                    figures.string()));
  ASSERT_EQ(status, 0) << out;
  // Every coordinate, speed and slot of the model appears in a figure's legend, and each of
  // the model's coordinate groups has its PNG.
  const nlohmann::json model =
      nlohmann::json::parse(Slurp(csv.parent_path() / "wind_turbine_dummy.meta.json"))["model"];
  for (const auto& [key, prefix] : {std::pair{"coordinates", "coordinates"},
                                    std::pair{"speeds", "speeds"},
                                    std::pair{"slots", "restoring-forces"}}) {
    for (const auto& entry : model[key]) {
      const std::string name = entry["name"];
      bool drawn = false;
      for (const auto& file : fs::directory_iterator(figures)) {
        const std::string stem = file.path().stem().string();
        if (file.path().extension() == ".svg" && stem.rfind(prefix, 0) == 0 &&
            Slurp(file.path()).find(">" + name + "<") != std::string::npos) {
          drawn = fs::exists(figures / (stem + ".png"));
        }
      }
      EXPECT_TRUE(drawn) << key << " " << name;
    }
  }
  // The groups: the tower (m), the azimuth (rad, large) and the blade rotations (rad, small).
  for (const char* png : {"coordinates-x_t.png", "coordinates-psi.png",
                          "coordinates-beta1-beta3.png", "restoring-forces.png"}) {
    EXPECT_TRUE(fs::exists(figures / png)) << png;
  }
  const std::string moments = Slurp(figures / "restoring-forces.svg");
  EXPECT_NE(moments.find("Restoring forces [N\u00b7m]"), std::string::npos);
  // Lab units: the tower in mm; a wrong unit is a configuration error.
  const auto [lab, lab_out] = Hybridtest(fmt::format("plot {} --out {} --units mm,kN",
                                                     csv.string(), (figures / "lab").string()));
  ASSERT_EQ(lab, 0) << lab_out;
  EXPECT_NE(Slurp(figures / "lab" / "coordinates-x_t.svg").find("[mm]"), std::string::npos);
  EXPECT_NE(Slurp(figures / "lab" / "restoring-forces.svg").find("[kN\u00b7m]"),
            std::string::npos);
  const auto [bad, bad_out] = Hybridtest(fmt::format("plot {} --units inch", csv.string()));
  EXPECT_EQ(bad, 2) << bad_out;
  EXPECT_NE(bad_out.find("--units"), std::string::npos) << bad_out;
}

TEST(ModelFileFigures, ReportLeadsWithTheSummary) {
  const fs::path csv = TurbineRun();
  const fs::path html = csv.parent_path() / "report.html";
  const auto [status, out] = Hybridtest(fmt::format("report {} --out {}", csv.string(),
                                                    html.string()));
  ASSERT_EQ(status, 0) << out;
  const std::string text = Slurp(html);
  const auto summary = text.find("id=\"summary\""), figures = text.find("id=\"figures\""),
             configuration = text.find("id=\"configuration\"");
  ASSERT_NE(summary, std::string::npos);
  EXPECT_LT(summary, figures);
  EXPECT_LT(figures, configuration);
  EXPECT_NE(text.find("Initial stiffness K0"), std::string::npos);
  EXPECT_NE(text.find("200000 N\u00b7m/rad"), std::string::npos);  // the law's K0 of r1
  EXPECT_EQ(text.find("\"k0\""), std::string::npos);                // not raw JSON
}

TEST(ModelFileFigures, EomLabelsMomentSlotsWithTheirUnit) {
  const auto [status, out] = Hybridtest(fmt::format(
      "eom {}/examples/04_wind_turbine/simulation.yaml --time 0 --state "
      "0,0,0.01,0,0,0,0,0,0,0",
      kSource));
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("2000 [N\u00b7m] r1"), std::string::npos) << out;
  EXPECT_EQ(out.find("[N]:"), std::string::npos) << out;
}

}  // namespace
}  // namespace hybridtest
