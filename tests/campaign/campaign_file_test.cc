// The campaign file: key paths, the product of table × grid × seeds, case ids, the reference,
// the errors, and the case's config (overrides applied, files rebased to the case's folder).
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "support/temp_dir.h"

namespace hybridtest::campaign {
namespace {

namespace fs = std::filesystem;
using test_support::FreshTempDir;
using test_support::WriteText;

constexpr const char* kBase =
    "model:\n  name: rotor\n  blades: 3\nintegrator:\n  tableau: heun\n  dt: 0.001\n"
    "duration: 1.0\noutput:\n  csv: results/base.csv\n";

fs::path WriteCampaign(const std::string& campaign_text, const std::string& name) {
  const fs::path dir = FreshTempDir("campaign_file_" + name);
  WriteText(dir / "base.yaml", kBase);
  WriteText(dir / "c.yaml", campaign_text);
  return dir;
}

TEST(CampaignKeyPath, SplitsAtDotsButKeepsAParameterWhole) {
  EXPECT_EQ(SplitKeyPath("model.parameters.blade1.k_b"),
            (std::vector<std::string>{"model", "parameters", "blade1.k_b"}));
  EXPECT_EQ(SplitKeyPath("integrator.dt"), (std::vector<std::string>{"integrator", "dt"}));
  EXPECT_EQ(SplitKeyPath("duration"), (std::vector<std::string>{"duration"}));
  EXPECT_THROW(SplitKeyPath("model..x"), ConfigError);
}

TEST(CampaignKeyPath, SetCreatesSectionsAndRefusesToDescendIntoAValue) {
  YAML::Node root = YAML::Load(kBase);
  SetKeyPath(root, "model.parameters.blade1.k_b", "5250");
  EXPECT_EQ(root["model"]["parameters"]["blade1.k_b"].as<double>(), 5250.0);
  SetKeyPath(root, "integrator.dt", "0.0005");
  EXPECT_EQ(root["integrator"]["dt"].as<double>(), 0.0005);
  EXPECT_THROW(SetKeyPath(root, "duration.x", "1"), ConfigError);
}

TEST(CampaignFile, GridIsTheProductInOrderWithReadableIds) {
  const fs::path dir = WriteCampaign(
      "base: base.yaml\ngrid:\n  model.parameters.f_w: [50, 100]\n"
      "  model.parameters.blade1.k_b: [5250, 7200, 9000]\nmetrics: [max_abs(q1), error(q1)]\n"
      "reference: {model.parameters.f_w: 100.0, model.parameters.blade1.k_b: 7200}\n", "grid");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  ASSERT_EQ(c.cases.size(), 6u);
  EXPECT_EQ(c.cases[0].id, "c0-f_w=50-blade1.k_b=5250");
  EXPECT_EQ(c.cases[5].id, "c5-f_w=100-blade1.k_b=9000");
  EXPECT_EQ(c.cases[4].params[0].second, "100");
  EXPECT_EQ(c.cases[4].params[1].second, "7200");
  EXPECT_EQ(c.reference, 4);  // 100.0 matches 100 as a number
  EXPECT_EQ(c.varied, (std::vector<std::string>{"model.parameters.f_w",
                                                "model.parameters.blade1.k_b"}));
  ASSERT_EQ(c.metrics.size(), 2u);
  EXPECT_EQ(c.metrics[1].kind, MetricSpec::kError);
  EXPECT_EQ(c.metrics[1].channel, "q1");
  EXPECT_EQ(c.command, CaseCommand::kSimulate);
}

TEST(CampaignFile, TableTimesSeedsKeepsTheTablesIds) {
  const fs::path dir = WriteCampaign(
      "base: base.yaml\ntable: cases.csv\nseeds: {key: test.seed, count: 2, first: 7}\n",
      "table");
  WriteText(dir / "cases.csv", "id,model.parameters.f_w,duration\n"
                               "calm,10,0.5\n# a comment\nstorm, 300 ,0.25\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  ASSERT_EQ(c.cases.size(), 4u);
  EXPECT_EQ(c.cases[0].id, "calm-seed=7");
  EXPECT_EQ(c.cases[3].id, "storm-seed=8");
  EXPECT_EQ(c.cases[3].params[0].second, "300");
  EXPECT_EQ(c.cases[3].params[2], (std::pair<std::string, std::string>{"test.seed", "8"}));
}

TEST(CampaignFile, ErrorsNameTheKeyAndTheFix) {
  auto message = [](const std::string& text, const std::string& name) {
    const fs::path dir = WriteCampaign(text, name);
    WriteText(dir / "dup.csv", "id,duration\na,1\na,2\n");
    try {
      LoadCampaign((dir / "c.yaml").string());
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("base: base.yaml\ngird: {duration: [1]}\n", "typo").find("gird"),
            std::string::npos);
  EXPECT_NE(message("base: base.yaml\n", "none").find("grid"), std::string::npos);
  EXPECT_NE(message("base: base.yaml\ngrid: {duration: []}\n", "empty").find("grid.duration"),
            std::string::npos);
  EXPECT_NE(message("base: base.yaml\ntable: dup.csv\n", "dup").find("two cases"),
            std::string::npos);
  EXPECT_NE(message("base: base.yaml\ngrid: {duration: [1]}\nmetrics: [peak(q1)]\n", "metric")
                .find("max_abs(q1)"), std::string::npos);
  EXPECT_NE(message("base: base.yaml\ngrid: {duration: [1]}\nmetrics: [error(q1)]\n", "ref")
                .find("reference"), std::string::npos);
  EXPECT_NE(message("base: missing.yaml\ngrid: {duration: [1]}\n", "base").find("missing.yaml"),
            std::string::npos);
  EXPECT_NE(message("base: base.yaml\ncommand: sweep\ngrid: {duration: [1]}\n", "cmd")
                .find("simulate, run or plan"), std::string::npos);
}

TEST(CampaignFile, CaseConfigAppliesTheValuesAndRebasesFiles) {
  const fs::path dir = WriteCampaign("base: sub/base.yaml\nset: {duration: 0.5}\n"
                             "grid: {model.parameters.blade1.k_b: [5250]}\n", "config");
  fs::create_directories(dir / "sub");
  WriteText(dir / "sub" / "base.yaml",
            "model: {file: models/m.yaml}\nintegrator: {tableau: heun, dt: 0.001}\n"
            "duration: 1\noutput: {csv: x.csv}\nsubstructures:\n  r1:\n    type: physical\n"
            "    transfer: {type: emulated, config: bench.yaml}\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  const fs::path case_dir = dir / "out" / "cases" / c.cases[0].id;
  const YAML::Node cfg = YAML::Load(CaseConfigText(c, 0, case_dir.string()));
  EXPECT_EQ(cfg["duration"].as<double>(), 0.5);
  EXPECT_EQ(cfg["model"]["parameters"]["blade1.k_b"].as<double>(), 5250.0);
  EXPECT_FALSE(cfg["output"]);
  EXPECT_EQ(cfg["model"]["file"].as<std::string>(), "../../../sub/models/m.yaml");
  EXPECT_EQ(cfg["substructures"]["r1"]["transfer"]["config"].as<std::string>(),
            "../../../sub/bench.yaml");
}

TEST(CampaignFile, CaseConfigIsAValidRunConfig) {
  const fs::path dir =
      WriteCampaign("base: base.yaml\ngrid: {model.parameters.f_w: [42]}\n", "valid");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  const fs::path case_dir = dir / "cases" / c.cases[0].id;
  fs::create_directories(case_dir);
  WriteText(case_dir / "config.yaml", CaseConfigText(c, 0, case_dir.string()));
  const io::SimulationConfig cfg = io::LoadSimulationConfig((case_dir / "config.yaml").string());
  EXPECT_EQ(cfg.model.parameters.Get("f_w"), 42.0);
  EXPECT_TRUE(cfg.output_csv.empty());
}

TEST(CampaignFile, AKeyInsideABenchFileCopiesTheBenchInline) {
  const fs::path dir = WriteCampaign(
      "base: base.yaml\nseeds: {key: substructures.r1.transfer.bench.seed, values: [7]}\n",
      "bench");
  WriteText(dir / "base.yaml",
            "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
            "duration: 1\nsubstructures:\n  r1:\n    type: physical\n"
            "    transfer: {type: emulated, config: bench.yaml}\n");
  WriteText(dir / "bench.yaml", "bench:\n  seed: 1\n  p0_mm: 2\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  EXPECT_EQ(c.cases[0].id, "c0-seed=7");
  const YAML::Node cfg = YAML::Load(CaseConfigText(c, 0, (dir / "case").string()));
  const YAML::Node transfer = cfg["substructures"]["r1"]["transfer"];
  EXPECT_FALSE(transfer["config"]);
  EXPECT_EQ(transfer["bench"]["seed"].as<int>(), 7);
  EXPECT_EQ(transfer["bench"]["p0_mm"].as<double>(), 2.0);
}

TEST(CampaignFile, CaseIdsAreSafeFolderNames) {
  EXPECT_TRUE(IsValidCaseId("c01-f_w=25-blade1.k_b=5250"));
  EXPECT_FALSE(IsValidCaseId(""));
  EXPECT_FALSE(IsValidCaseId(".."));
  EXPECT_FALSE(IsValidCaseId("a/b"));
  EXPECT_FALSE(IsValidCaseId("a b"));
  EXPECT_FALSE(IsValidCaseId(std::string(121, 'a')));
}

}  // namespace
}  // namespace hybridtest::campaign
