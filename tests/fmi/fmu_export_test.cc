// The contract of `hybridtest export-fmu` (issue 35): examples/rotor/dummy.yaml exported as an
// FMU (FMI 2.0 and 3.0), loaded by the project's own importer (fmi/fmu_instance.h) and stepped
// at 1 ms with the restoring force of a linear blade (k_b d) fed back, reproduces `simulate
// examples/rotor/numerical.yaml` within 1e-9 m; every variable of its description has a unit
// with a definition; get/set FMU state (and its serialized form) continues exactly; its binary
// exports every function the standard's header declares for co-simulation (issue 48).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fmi/fmi_entry_points.h"
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

// An instance of the FMU at `fmu` (unpacked in `unpacked`), initialized with `parameters`.
Exported Load(const fs::path& fmu, const fs::path& unpacked,
              const std::vector<std::pair<std::string, double>>& parameters = {}) {
  Exported e;
  e.fmu = fmu;
  if (!fs::exists(unpacked)) fmi::ExtractArchive(e.fmu.string(), unpacked.string());
  e.md = fmi::ParseModelDescription(fmi::ReadMember(e.fmu.string(), "modelDescription.xml"),
                                    e.fmu.string());
  e.instance = fmi::LoadFmu(unpacked.string(), e.md, e.fmu.string(), "rotor", fmi::StderrLog());
  std::vector<fmi::FmuInstance::Value> values;
  for (const auto& [name, value] : parameters) {
    EXPECT_NE(e.md.Find(name), nullptr) << "the FMU declares no parameter " << name;
    if (e.md.Find(name) != nullptr) values.push_back({e.md.Find(name), value});
  }
  e.instance->Initialize(0.0, values);
  return e;
}

Exported Export(const fs::path& dir, int version,
               const std::vector<std::pair<std::string, double>>& parameters = {}) {
  fs::create_directories(dir);
  const fs::path fmu = dir / ("rotor" + std::to_string(version) + ".fmu");
  RunToEnd({"export-fmu", kSource + "/examples/rotor/dummy.yaml", "--out", fmu.string(),
            "--fmi-version", std::to_string(version)},
           dir / "export.log");
  Exported e = Load(fmu, dir / ("unpacked" + std::to_string(version)), parameters);
  // One name for the model: modelName is the identifier (the binary's and the --out stem), not
  // the config's stem (dummy), as an importer's list of models shows it.
  EXPECT_EQ(e.md.model_name, "rotor" + std::to_string(version));
  EXPECT_EQ(e.md.model_identifier, e.md.model_name);
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
  // Its binary exports every function a strict importer requires (issue 48).
  fmi::test::ExpectEveryEntryPoint(e.fmu.string());
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

// Issue 48: each parameter has one meaning. dummy.yaml gives no blade its own f_w, so the FMU
// declares the all-blades f_w and no blade<i>.f_w; a master that applies every declared start
// value gets the start run bit for bit, and with f_w = 50 the f_w = 50 run; f_w reads back
// the value in effect. A state serialized at t = 1 s of the f_w = 50 run and set into a fresh
// instance (f_w = 100) continues as the original did: the state brings its parameters.
TEST(FmuExportParameters, StartValuesChangeNothingAndTheStateCarriesTheParameters) {
  const fs::path dir = ResumeTestDir("fmu_export_meaning");
  Exported start = Export(dir, 3);
  const fs::path unpacked = dir / "unpacked3";
  // export-fmu wrote the variable table beside the FMU (and printed it): r1's value reference.
  const auto table = ReadLines(dir / "rotor3.variables.csv");
  ASSERT_FALSE(table.empty());
  EXPECT_EQ(table[0], "name,value_reference,causality,unit,start,description");
  const std::string r1 = "\"r1\"," + std::to_string(start.vr("r1")) + ",input,\"N\",";
  EXPECT_EQ(std::count_if(table.begin(), table.end(),
                          [&](const std::string& line) { return line.rfind(r1, 0) == 0; }),
            1) << r1;
  EXPECT_EQ(table.size(), start.md.variables.size() + 1);
  EXPECT_EQ(start.md.Find("blade1.f_w"), nullptr) << "blade1.f_w and f_w would both be declared";
  ASSERT_NE(start.md.Find("blade2.psi"), nullptr);  // a per-blade parameter of its own
  std::vector<std::pair<std::string, double>> starts, blade_starts;
  for (const auto& v : start.md.variables) {
    if (v.causality != "parameter") continue;
    starts.emplace_back(v.name, std::stod(v.start.value()));
    if (v.name.rfind("blade", 0) == 0) blade_starts.emplace_back(v.name, starts.back().second);
  }
  Exported all_starts = Load(start.fmu, unpacked, starts);
  std::vector<std::pair<std::string, double>> fifty_all = blade_starts;
  fifty_all.emplace_back("f_w", 50.0);
  Exported fifty = Load(start.fmu, unpacked, {{"f_w", 50.0}});
  Exported fifty_with_starts = Load(start.fmu, unpacked, fifty_all);
  std::vector<double> f_w(1);
  fifty_with_starts.instance->GetReal({fifty.vr("f_w")}, f_w);
  EXPECT_EQ(f_w[0], 50.0);  // the value in effect
  const std::vector<unsigned> q_vr{start.vr("q1"), start.vr("q2"), start.vr("q4")};
  std::vector<double> q_start, q_fifty;
  int starts_differ = 0, fifty_differ = 0;  // steps whose q is not bit-identical
  for (int n = 0; n < 1000; ++n) {
    q_start = Step(start, n * 0.001, q_vr);
    starts_differ += Step(all_starts, n * 0.001, q_vr) != q_start;
    q_fifty = Step(fifty, n * 0.001, q_vr);
    fifty_differ += Step(fifty_with_starts, n * 0.001, q_vr) != q_fifty;
  }
  EXPECT_EQ(starts_differ, 0) << "every parameter set to its start value";
  EXPECT_EQ(fifty_differ, 0) << "f_w = 50 and every per-blade start value";
  EXPECT_GT(std::abs(q_fifty[0] - q_start[0]), 1e-6);  // f_w reached the model
  // The state of the f_w = 50 run at t = 1 s, set into a fresh f_w = 100 instance.
  fifty.instance->SnapshotState();
  const std::string bytes = fifty.instance->SerializeSnapshot();
  Exported fresh = Load(start.fmu, unpacked);
  fresh.instance->DeserializeIntoSnapshot(bytes);
  fresh.instance->RestoreSnapshot();
  fresh.instance->GetReal({fresh.vr("f_w")}, f_w);
  EXPECT_EQ(f_w[0], 50.0);
  int continued_differ = 0;
  for (int n = 1000; n < 1300; ++n) {
    continued_differ += Step(fresh, n * 0.001, q_vr) != Step(fifty, n * 0.001, q_vr);
  }
  EXPECT_EQ(continued_differ, 0) << "the deserialized state continued otherwise";
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
