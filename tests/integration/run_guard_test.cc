// One master per run and a state that cannot lie (docs/safety.md, "One master per run",
// "Resuming a run"), with real processes: two resumes of one killed run, a resume of a live
// run, run states edited by hand, resumes from another directory, and --out onto the run's
// own inputs and onto a device.
#include <sys/stat.h>

#include "hybridtest/runner/run_state.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kIdeal = kSource + "/tests/data/resume-emulated-ideal.yaml";

std::string FileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// In `dir`: reference.csv, kIdeal run to the end, and k.csv, the same run killed (SIGKILL)
// about 40 % of the way. Returns k.csv's path; fails the test if the run ended first.
fs::path ReferenceAndKilledRun(const fs::path& dir) {
  const fs::path reference = dir / "reference.csv";
  EXPECT_EQ(RunToEnd(RunArgs(kIdeal, reference), dir / "reference.log"), 0);
  const fs::path csv = dir / "k.csv";
  EXPECT_TRUE(RunAndSignalAt(RunArgs(kIdeal, csv), csv, fs::file_size(reference) * 2 / 5,
                             SIGKILL, dir / "run.log", 128 + SIGKILL));
  return csv;
}

TEST(OneMasterPerRun, TwoResumesThirtyMillisecondsApartOneProceeds) {
  const fs::path dir = ResumeTestDir("two_masters");
  const fs::path reference = dir / "reference.csv";
  const fs::path csv = ReferenceAndKilledRun(dir);
  ASSERT_FALSE(::testing::Test::HasFailure());
  Child first(HybridtestArgv({"resume", csv.string(), "--quiet"}), dir / "first.log");
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  Child second(HybridtestArgv({"resume", csv.string(), "--quiet"}), dir / "second.log");
  const int a = first.WaitExit(120.0);
  const int b = second.WaitExit(120.0);
  std::cout << "[ exit statuses of the two resumes: " << a << ", " << b << " ]\n";
  ASSERT_EQ(std::min(a, b), 0) << first.output() << second.output();
  ASSERT_EQ(std::max(a, b), 2) << first.output() << second.output();
  const std::string refused = a == 2 ? first.output() : second.output();
  EXPECT_NE(refused.find("in use by another hybridtest process"), std::string::npos) << refused;
  EXPECT_NE(refused.find("pid "), std::string::npos) << refused;
  EXPECT_NE(refused.find("k.lock"), std::string::npos) << refused;
  // The journal is the uninterrupted run's in t, q, u, r (and every other channel but the
  // bench's lab time), with one resume recorded.
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), /*skip_lab_time=*/true);
  const auto sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["status"], "completed");
  EXPECT_EQ(sidecar["resumes"].size(), 1u);
  fs::remove_all(dir);
}

TEST(OneMasterPerRun, AResumeOrAnOverwriteOfALiveRunIsRefused) {
  const fs::path dir = ResumeTestDir("live_run");
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(kIdeal, reference), dir / "reference.log"), 0);
  const fs::path csv = dir / "k.csv";
  Child live(HybridtestArgv(RunArgs(kIdeal, csv)), dir / "live.log");
  // Wait for the live run's first rows (its lock is held before any of them).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::error_code ec;
  while (fs::file_size(csv, ec) < 4096 || ec) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the live run wrote nothing";
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto [resume_status, resume_output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  Child overwrite(HybridtestArgv({"run", kIdeal, "--out", csv.string(), "--overwrite", "--quiet"}),
                  dir / "overwrite.log");
  const int overwrite_status = overwrite.WaitExit(60.0);
  const int live_status = live.WaitExit(120.0);
  EXPECT_EQ(resume_status, 2) << resume_output;
  EXPECT_NE(resume_output.find("in use by another hybridtest process"), std::string::npos)
      << resume_output;
  EXPECT_EQ(overwrite_status, 2) << overwrite.output();
  EXPECT_NE(overwrite.output().find("in use by another hybridtest process"), std::string::npos)
      << overwrite.output();
  ASSERT_EQ(live_status, 0) << live.output();
  // The live run completed unchanged: its journal is the reference's, lab time included.
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), /*skip_lab_time=*/false);
  EXPECT_EQ(Sidecar(csv)["status"], "completed");
  EXPECT_FALSE(Sidecar(csv).contains("resumes"));
  fs::remove_all(dir);
}

// Rewrites the run state of `csv` with `edit`; with `fix_checksum`, the checksum is made right
// again (a deliberate edit rather than damage: the journal check must still refuse it).
void EditState(const fs::path& csv, const std::function<void(nlohmann::json&)>& edit,
               bool fix_checksum) {
  const fs::path path = runner::RunStatePath(csv.string());
  nlohmann::json state = nlohmann::json::parse(FileText(path));
  edit(state);
  if (fix_checksum) state["checksum"] = runner::RunStateChecksum(state);
  std::ofstream(path, std::ios::trunc) << state.dump();
}

TEST(AStateThatCannotLie, EditedStatesAreRefusedAndTheJournalIsUnchanged) {
  const fs::path dir = ResumeTestDir("edited_state");
  const fs::path reference = dir / "reference.csv";
  const fs::path csv = ReferenceAndKilledRun(dir);
  ASSERT_FALSE(::testing::Test::HasFailure());
  const fs::path state_path = runner::RunStatePath(csv.string());
  const std::string original_state = FileText(state_path);
  struct Case {
    const char* name;
    std::function<void(nlohmann::json&)> edit;
    bool fix_checksum;
    const char* message;
  };
  const std::vector<Case> cases{
      {"rows: 2", [](nlohmann::json& s) { s["rows"] = 2; }, false, "checksum does not match"},
      {"rows: 2, checksum recomputed", [](nlohmann::json& s) { s["rows"] = 2; }, true,
       "damaged run state"},
      {"rows: 2 and journal.rows: 1, checksum recomputed",
       [](nlohmann::json& s) {
         s["rows"] = 2;
         s["journal"]["rows"] = 1;
       },
       // Refused by the state's own consistency (rows = step + 1) before the journal is read.
       true, "damaged run state"},
      {"last command + 19 mm",
       [](nlohmann::json& s) {
         // One row per actuator: command, position, force [m, m, N], lab time [s].
         auto& last = s["substructures"][0]["state"]["last"][0];
         last[0] = last[0].get<double>() + 0.019;
       },
       false, "checksum does not match"},
      {"last command + 19 mm, checksum recomputed",
       [](nlohmann::json& s) {
         auto& last = s["substructures"][0]["state"]["last"][0];
         last[0] = last[0].get<double>() + 0.019;
       },
       true, "the parts of the state disagree"},
      {"row and last command + 19 mm, checksum recomputed",
       [](nlohmann::json& s) {
         auto& last = s["substructures"][0]["state"]["last"][0];
         last[0] = last[0].get<double>() + 0.019;
         s["row"][12] = last[0];  // t, q1..q4, u1..u4, r1..r3, r1_command, ...
       },
       true, "does not belong to this journal"},
      {"another scheme.step and t, checksum recomputed",
       [](nlohmann::json& s) { s["scheme"]["t"] = 8.07; }, true, "disagree"},
      {"truncated", [](nlohmann::json&) {}, false, "not valid JSON"},
  };
  // Killed between the state and its row, the journal cannot show the committed row: a
  // consistent forgery of that row is then beyond the journal check (docs/safety.md).
  const runner::RunState state = runner::LoadRunState(state_path.string());
  const bool row_on_disk =
      runner::ReadJournalRows(csv.string(), {}).complete >= state.rows;
  std::cout << "[ committed row on disk at the kill: " << row_on_disk << " ]\n";
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    if (!row_on_disk && std::string(c.name).rfind("row and", 0) == 0) continue;
    std::ofstream(state_path, std::ios::trunc) << original_state;
    EditState(csv, c.edit, c.fix_checksum);
    if (std::string(c.name) == "truncated") {
      std::ofstream(state_path, std::ios::trunc) << original_state.substr(0, original_state.size() / 2);
    }
    const std::string journal_before = FileText(csv);
    const std::string sidecar_before = FileText(fs::path(csv).replace_extension(".meta.json"));
    const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
    EXPECT_EQ(status, 2) << output;
    EXPECT_NE(output.find(c.message), std::string::npos) << output;
    EXPECT_EQ(FileText(csv), journal_before);
    EXPECT_EQ(FileText(fs::path(csv).replace_extension(".meta.json")), sidecar_before);
  }
  // The untouched state still resumes to the uninterrupted journal.
  std::ofstream(state_path, std::ios::trunc) << original_state;
  const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), /*skip_lab_time=*/true);
  fs::remove_all(dir);
}

// A run whose config reads a model file, in its own folder; resumed from another directory
// that holds a different model file at the same relative path.
TEST(AStateThatCannotLie, ResumeUsesTheRunsOwnFilesNeverTheCurrentDirectorys) {
  const fs::path dir = ResumeTestDir("other_dir");
  fs::create_directories(dir / "lab" / "models");
  fs::create_directories(dir / "elsewhere" / "models");
  fs::copy_file(kSource + "/examples/models/rotor.yaml", dir / "lab" / "models" / "rotor.yaml");
  // The other directory's model: the same file with the blade mass doubled.
  std::string other = FileText(kSource + "/examples/models/rotor.yaml");
  std::ofstream(dir / "elsewhere" / "models" / "rotor.yaml") << other << "\n# edited\n";
  const std::string config =
      "model: {file: models/rotor.yaml}\n"
      "integrator: {tableau: heun, dt: 0.001}\n"
      "duration: 10.0\n";
  std::ofstream(dir / "lab" / "run.yaml") << config;
  const fs::path reference = dir / "lab" / "reference.csv";
  ASSERT_EQ(RunToEnd({"simulate", (dir / "lab" / "run.yaml").string(), "--out",
                      reference.string(), "--quiet"}, dir / "reference.log"), 0);
  const fs::path csv = dir / "lab" / "k.csv";
  // Relative paths, started from the lab folder, as an operator would.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir / "lab");
  bool killed = false;
  for (int attempt = 0; attempt < 5 && !killed; ++attempt) {
    fs::remove(csv);
    fs::remove(dir / "lab" / "k.meta.json");
    fs::remove(dir / "lab" / "k.state.json");
    killed = RunAndSignalAt({"simulate", "run.yaml", "--out", "k.csv", "--quiet"}, csv,
                            fs::file_size(reference) / 2, SIGKILL, dir / "run.log",
                            128 + SIGKILL);
  }
  fs::current_path(dir / "elsewhere");
  ASSERT_TRUE(killed);
  const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  fs::current_path(cwd);
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), /*skip_lab_time=*/false);
  const auto inputs = Sidecar(csv)["extra"]["inputs"];
  ASSERT_EQ(inputs.size(), 2u) << inputs.dump();
  EXPECT_EQ(inputs[0]["path"], "run.yaml");
  EXPECT_EQ(inputs[1]["path"], "models/rotor.yaml");

  // The run's own model file edited after it started: resume refuses, naming it.
  fs::remove(csv);
  fs::remove(dir / "lab" / "k.meta.json");
  fs::remove(dir / "lab" / "k.state.json");
  ASSERT_TRUE(RunAndSignalAt({"simulate", (dir / "lab" / "run.yaml").string(), "--out",
                              csv.string(), "--quiet"},
                             csv, fs::file_size(reference) / 2, SIGKILL, dir / "run.log",
                             128 + SIGKILL));
  std::ofstream(dir / "lab" / "models" / "rotor.yaml", std::ios::app) << "\n# edited\n";
  const std::string journal_before = FileText(csv);
  const auto [edited_status, edited_output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  EXPECT_EQ(edited_status, 2) << edited_output;
  EXPECT_NE(edited_output.find("models/rotor.yaml (model file): changed since the run started"),
            std::string::npos) << edited_output;
  EXPECT_EQ(FileText(csv), journal_before);
  fs::remove_all(dir);
}

// Killed between the journal's two publishing renames, a run has its CSV but its sidecar is
// still "<run>.meta.json.partial": resume completes the rename and continues.
TEST(AStateThatCannotLie, ASidecarLeftStagedIsPublishedByResume) {
  const fs::path dir = ResumeTestDir("staged_sidecar");
  const std::string numerical = kSource + "/examples/rotor/numerical.yaml";
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd({"simulate", numerical, "--out", reference.string(), "--quiet"},
                     dir / "reference.log"), 0);
  const fs::path csv = dir / "k.csv";
  ASSERT_TRUE(RunAndSignalAt({"simulate", numerical, "--out", csv.string(), "--quiet"}, csv,
                             fs::file_size(reference) / 2, SIGKILL, dir / "run.log",
                             128 + SIGKILL));
  fs::rename(dir / "k.meta.json", dir / "k.meta.json.partial");
  const auto [status, output] = Resume(csv, {}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("completed from"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "k.meta.json.partial"));
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), /*skip_lab_time=*/false);
  fs::remove_all(dir);
}

// An emulated bench's test fault fires once: a run stopped by it is resumed past it, and the
// fault does not fire again at the same command.
TEST(AStateThatCannotLie, ATestFaultThatStoppedTheRunDoesNotFireAgainOnResume) {
  const fs::path dir = ResumeTestDir("fault_once");
  std::string bench = FileText(kSource + "/examples/rotor/bench-ideal.yaml");
  bench += "  faults: [{at: 60, kind: nan}]\n";
  std::ofstream(dir / "bench.yaml") << bench;
  std::ofstream(dir / "run.yaml")
      << "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
         "duration: 0.1\nsubstructures:\n  r1:\n    type: physical\n"
         "    transfer: {type: emulated, config: bench.yaml}\n    setup: {p0: 0.020}\n"
         "    safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005, "
         "force_soft: 8000, force_hard: 10000, timeout: 5}\n";
  const fs::path csv = dir / "k.csv";
  Child run(HybridtestArgv({"run", (dir / "run.yaml").string(), "--out", csv.string(), "--quiet"}),
            dir / "run.log");
  ASSERT_EQ(run.WaitExit(60.0), 3) << run.output();  // the NaN force: a safety stop
  EXPECT_EQ(Sidecar(csv)["statistics"]["stop"]["commands_received"][0], 60);
  const auto [status, output] = Resume(csv, {"--after-safety-stop", "--quiet"}, dir / "r.log");
  EXPECT_EQ(status, 0) << output;
  EXPECT_EQ(Sidecar(csv)["status"], "completed");
  fs::remove_all(dir);
}

TEST(OutputsGuarded, OntoTheModelTheTokenOrADeviceIsRefused) {
  const fs::path dir = ResumeTestDir("out_guard");
  fs::copy_file(kSource + "/examples/models/rotor.yaml", dir / "rotor.yaml");
  std::ofstream(dir / "token.txt") << "a-shared-secret-of-32-characters\n";
  std::ofstream(dir / "sim.yaml") << "model: {file: rotor.yaml}\n"
                                     "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n";
  std::ofstream(dir / "remote.yaml")
      << "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
         "duration: 0.01\nsubstructures:\n  r1:\n    type: physical\n"
         "    transfer: {type: remote, address: '127.0.0.1:1', token_file: token.txt}\n"
         "    safety: defaults\n";
  const std::string model_before = FileText(dir / "rotor.yaml");
  const std::string token_before = FileText(dir / "token.txt");
  struct Case {
    std::vector<std::string> args;
    const char* message;
  };
  const std::vector<Case> cases{
      {{"simulate", (dir / "sim.yaml").string(), "--out", (dir / "rotor.yaml").string(),
        "--overwrite"}, "a file it reads"},
      {{"run", (dir / "remote.yaml").string(), "--out", (dir / "token.txt").string(),
        "--overwrite"}, "a file it reads"},
      {{"simulate", (dir / "sim.yaml").string(), "--out", "/dev/null", "--overwrite"},
       "is a device"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args[3]);
    Child child(HybridtestArgv(c.args), dir / "out.log");
    EXPECT_EQ(child.WaitExit(60.0), 2) << child.output();
    EXPECT_NE(child.output().find(c.message), std::string::npos) << child.output();
  }
  EXPECT_EQ(FileText(dir / "rotor.yaml"), model_before);
  EXPECT_EQ(FileText(dir / "token.txt"), token_before);
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null is no longer a device";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
