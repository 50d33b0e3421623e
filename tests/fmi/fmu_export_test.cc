// The contract of `hybridtest export-fmu` (issue 35): examples/rotor/dummy.yaml exported as an
// FMU (FMI 2.0 and 3.0), loaded by the project's own importer (fmi/fmu_instance.h) and stepped
// at 1 ms with the restoring force of a linear blade (k_b d) fed back, reproduces `simulate
// examples/rotor/numerical.yaml` within 1e-9 m; every variable of its description has a unit
// with a definition; get/set FMU state (and its serialized form) continues exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/fmu_instance.h"
#include "hybridtest/fmi/model_description.h"
#include "integration/child_process.h"
#include "integration/resume_support.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

constexpr double kBlade = 7200.0;  // k_b [N/m]

struct Exported {
  fs::path fmu;
  fmi::ModelDescription md;
  std::unique_ptr<fmi::FmuInstance> instance;
  unsigned vr(const std::string& name) const {
    const fmi::ModelVariable* v = md.Find(name);
    EXPECT_NE(v, nullptr) << name;
    return v != nullptr ? v->value_reference : 0;
  }
};

Exported Export(const fs::path& dir, int version,
               const std::vector<std::pair<std::string, double>>& parameters = {}) {
  Exported e;
  fs::create_directories(dir);
  e.fmu = dir / ("rotor" + std::to_string(version) + ".fmu");
  RunToEnd({"export-fmu", kSource + "/examples/rotor/dummy.yaml", "--out", e.fmu.string(),
            "--fmi-version", std::to_string(version)},
           dir / "export.log");
  const fs::path unpacked = dir / ("unpacked" + std::to_string(version));
  fmi::ExtractArchive(e.fmu.string(), unpacked.string());
  e.md = fmi::ParseModelDescription(fmi::ReadMember(e.fmu.string(), "modelDescription.xml"),
                                    e.fmu.string());
  e.instance = fmi::LoadFmu(unpacked.string(), e.md, e.fmu.string(), "rotor", fmi::StderrLog());
  std::vector<fmi::FmuInstance::Value> values;
  for (const auto& [name, value] : parameters) values.push_back({e.md.Find(name), value});
  e.instance->Initialize(0.0, values);
  return e;
}

// One communication step of 1 ms with r1 = k_b d_r1 fed back; returns q.
std::vector<double> Step(Exported& e, double t, const std::vector<unsigned>& q_vr) {
  std::vector<double> d(1);
  e.instance->GetReal({e.vr("d_r1")}, d);
  e.instance->SetReal({e.vr("r1")}, {kBlade * d[0]});
  e.instance->DoStep(t, 0.001);
  std::vector<double> q(q_vr.size());
  e.instance->GetReal(q_vr, q);
  return q;
}

class FmuExport : public ::testing::TestWithParam<int> {};

TEST_P(FmuExport, LinearBladeFedBackReproducesSimulateAndEveryVariableHasAUnit) {
  const fs::path dir = ResumeTestDir("fmu_export_" + std::to_string(GetParam()));
  Exported e = Export(dir, GetParam());
  ASSERT_EQ(e.md.fmi_version, GetParam() == 3 ? "3.0" : "2.0");
  RunToEnd({"simulate", kSource + "/examples/rotor/numerical.yaml", "--out",
            (dir / "numerical.csv").string(), "--quiet"},
           dir / "simulate.log");
  const auto lines = ReadLines(dir / "numerical.csv");
  ASSERT_EQ(lines.size(), 10002u);
  const std::vector<unsigned> q_vr{e.vr("q1"), e.vr("q2"), e.vr("q3"), e.vr("q4")};
  double largest = 0.0, moved = 0.0;
  for (int n = 0; n < 10000; ++n) {
    const auto q = Step(e, n * 0.001, q_vr);
    const auto row = SplitCsv(lines[n + 2]);
    for (int i = 0; i < 4; ++i) {
      largest = std::max(largest, std::abs(q[i] - std::stod(row[1 + i])));
      moved = std::max(moved, std::abs(q[i]));
    }
  }
  EXPECT_LE(largest, 1e-9) << "largest |q_fmu − q_simulate| [m or rad]";
  EXPECT_GT(moved, 1e-3);  // the model moved: not two zero runs
  // Its description names every variable with a unit that has a definition.
  int inputs = 0, outputs = 0, parameters = 0;
  for (const auto& v : e.md.variables) {
    EXPECT_NE(e.md.UnitOf(v), nullptr) << v.name << " has no unit with a definition";
    inputs += v.causality == "input";
    outputs += v.causality == "output";
    parameters += v.causality == "parameter";
  }
  EXPECT_EQ(inputs, 1);        // r1
  EXPECT_EQ(outputs, 1 + 8);   // d_r1, q1..q4, u1..u4
  EXPECT_GT(parameters, 8);    // the rotor's parameters
  const fmi::ModelVariable* k_b = e.md.Find("k_b");
  ASSERT_NE(k_b, nullptr);
  EXPECT_EQ(k_b->unit, "N/m");
  EXPECT_EQ(e.md.UnitOf(*e.md.Find("q4"))->rad, 1);
  EXPECT_TRUE(e.md.can_get_and_set_state);
}

// The model's parameters are the FMU's: without wind and gravity the rotor stays at rest.
TEST_P(FmuExport, ParametersReachTheModel) {
  const fs::path dir = ResumeTestDir("fmu_export_parameters_" + std::to_string(GetParam()));
  Exported e = Export(dir, GetParam(), {{"f_w", 0.0}, {"g", 0.0}});
  const std::vector<unsigned> q_vr{e.vr("q1"), e.vr("q2"), e.vr("q3"), e.vr("q4")};
  std::vector<double> q;
  for (int n = 0; n < 500; ++n) q = Step(e, n * 0.001, q_vr);
  EXPECT_EQ(q, std::vector<double>(4, 0.0));
  Exported moving = Export(dir / "default", GetParam());
  for (int n = 0; n < 500; ++n) q = Step(moving, n * 0.001, q_vr);
  EXPECT_GT(std::abs(q[0]), 1e-6);
}

TEST_P(FmuExport, GetSetAndSerializedStateContinueExactlyAndBadStepsAreRefused) {
  const fs::path dir = ResumeTestDir("fmu_export_state_" + std::to_string(GetParam()));
  Exported e = Export(dir, GetParam());
  const std::vector<unsigned> q_vr{e.vr("q1"), e.vr("q4")};
  int n = 0;
  for (; n < 300; ++n) Step(e, n * 0.001, q_vr);
  e.instance->SnapshotState();
  const std::string bytes = e.instance->SerializeSnapshot();
  std::vector<double> first;
  for (int k = 0; k < 200; ++k) first = Step(e, (n + k) * 0.001, q_vr);
  e.instance->RestoreSnapshot();
  std::vector<double> again;
  for (int k = 0; k < 200; ++k) again = Step(e, (n + k) * 0.001, q_vr);
  EXPECT_EQ(again, first);
  e.instance->DeserializeIntoSnapshot(bytes);
  e.instance->RestoreSnapshot();
  std::vector<double> serialized;
  for (int k = 0; k < 200; ++k) serialized = Step(e, (n + k) * 0.001, q_vr);
  EXPECT_EQ(serialized, first);
  // A communication step that is not a whole number of dt is an FMU error, named.
  try {
    e.instance->DoStep((n + 200) * 0.001, 0.0015);
    FAIL() << "a step of 1.5 dt was taken";
  } catch (const hybridtest::TransferError& error) {
    EXPECT_NE(std::string(error.what()).find("whole number"), std::string::npos) << error.what();
  }
}

// What export-fmu refuses, with exit 2 and the reason: an FMI version other than 2 or 3, an
// output that is its own config, an adaptive scheme (an FMU steps at a fixed step).
TEST(FmuExportRefusal, ExitsTwoNamingTheReason) {
  const fs::path dir = ResumeTestDir("fmu_export_refusal");
  const std::string config = (dir / "dummy.yaml").string();
  fs::copy_file(kSource + "/examples/rotor/dummy.yaml", config);
  const std::string before = ReadLines(config).at(0);
  test_support::WriteText(dir / "adaptive.yaml",
                          "model: {name: rotor, blades: 3}\nintegrator: {scheme: mr-os, dt: 0.01, "
                          "substep: 0.001, adaptive: {tolerance: 1e-6}}\nduration: 1\n"
                          "substructures:\n  r1: {type: numerical, law: {type: linear, "
                          "stiffness: 7200}}\n");
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  };
  for (const Case& c : std::vector<Case>{
           {{config, "--out", (dir / "x.fmu").string(), "--fmi-version", "4"}, "--fmi-version 4"},
           {{config, "--out", config}, "--out"},
           {{(dir / "adaptive.yaml").string(), "--out", (dir / "a.fmu").string()}, "adaptive"}}) {
    std::vector<std::string> args{"export-fmu"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    Child child(HybridtestArgv(args), dir / "refusal.log");
    EXPECT_EQ(child.WaitExit(60.0), 2) << child.output();
    EXPECT_NE(child.output().find(c.expected), std::string::npos) << child.output();
  }
  EXPECT_EQ(ReadLines(config).at(0), before);  // the config survived
  EXPECT_FALSE(fs::exists(dir / "x.fmu"));
  EXPECT_FALSE(fs::exists(dir / "a.fmu"));
}

INSTANTIATE_TEST_SUITE_P(Versions, FmuExport, ::testing::Values(2, 3),
                         [](const auto& p) { return "Fmi" + std::to_string(p.param); });

}  // namespace
}  // namespace hybridtest::testing
