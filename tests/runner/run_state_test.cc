// RunState: the checksum, the agreement of its parts, and its check against the journal
// (run_state.h; docs/safety.md, "Resuming a run").
#include "hybridtest/runner/run_state.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <functional>
#include <limits>

#include "hybridtest/common/error.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

using ::testing::HasSubstr;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// A state of a 1-DOF run with one physical slot at row 2 (t = 0.002), saved before its row:
// the journal then held rows 0 and 1.
RunState ExampleState() {
  RunState s;
  s.rows = 3;
  s.stage_rows = 5;
  s.scheme = {{"scheme", "runge-kutta"}, {"step", 2}, {"t", 0.002},
              {"x", {4e-06, 0.004}}, {"r", {-0.0288}}, {"own", nullptr}};
  s.substructures = nlohmann::json::array(
      {{{"slot", "r1"},
        {"state", {{"last", {{"command_m", 0.020004}, {"position_m", 0.020004},
                             {"force_N", -0.0288}, {"lab_time_s", 2.5}}}}}}});
  s.row = {0.002, 4e-06, 0.004, -0.0288, 0.020004, 0.020004, -0.0288, 2.5};
  s.journal_rows = 2;
  s.journal_last_row = std::vector<double>{0.001, 1e-06, 0.002, kNaN, 0.020001, 0.020001,
                                           -0.0072, 1.25};
  s.inputs = nlohmann::json::array({{{"role", "config"}, {"path", "run.yaml"},
                                     {"sha256", std::string(64, '0')}}});
  return s;
}

const char kHeader[] = "t,q1,u1,r1,r1_command,r1_position,r1_force,r1_lab_time\n";
const char kRow0[] = "0,0,0,0,0.02,0.02,0,0\n";
const char kRow1[] = "0.001,1e-06,0.002,nan,0.020001,0.020001,-0.0072,1.25\n";
const char kRow2[] = "0.002,4.0000000000000002e-06,0.004,-0.0288,0.020004,0.020004,-0.0288,2.5\n";

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RunStateChecksum, RoundTripsAndRefusesAnyEdit) {
  const nlohmann::json j = ToJson(ExampleState());
  ASSERT_TRUE(j.contains("checksum"));
  const RunState back = RunStateFromJson(nlohmann::json::parse(j.dump()), "s.json");
  EXPECT_EQ(back.rows, 3);
  EXPECT_EQ(back.journal_rows, 2);
  ASSERT_TRUE(back.journal_last_row.has_value());
  EXPECT_TRUE(std::isnan((*back.journal_last_row)[3]));  // NaN survives as null
  for (const char* key : {"rows", "stage_rows"}) {
    nlohmann::json edited = j;
    edited[key] = 2;
    EXPECT_THAT(ErrorOf([&] { RunStateFromJson(edited, "s.json"); }),
                HasSubstr("checksum does not match")) << key;
  }
  nlohmann::json edited = j;
  edited["substructures"][0]["state"]["last"]["command_m"] = 0.039;
  EXPECT_THAT(ErrorOf([&] { RunStateFromJson(edited, "s.json"); }),
              HasSubstr("checksum does not match"));
  // Recomputed after the edit, the checksum passes but the parts disagree.
  edited["checksum"] = RunStateChecksum(edited);
  EXPECT_THAT(ErrorOf([&] { RunStateFromJson(edited, "s.json"); }),
              HasSubstr("the parts of the state disagree"));
  nlohmann::json old = j;
  old["version"] = 1;
  EXPECT_THAT(ErrorOf([&] { RunStateFromJson(old, "s.json"); }), HasSubstr("version 1"));
  // Found by fuzzing: a key of the wrong JSON type is a ConfigError, never an exception of
  // the JSON library (which the CLI would report as an internal error).
  for (const char* key : {"format", "version", "checksum", "rows", "row", "journal", "scheme"}) {
    nlohmann::json wrong = j;
    wrong[key] = nlohmann::json::array({1, "x"});
    wrong["checksum"] = RunStateChecksum(wrong);
    if (std::string(key) == "checksum") wrong[key] = nlohmann::json::array();
    EXPECT_NE(ErrorOf([&] { RunStateFromJson(wrong, "s.json"); }), "(no error)") << key;
  }
  nlohmann::json step = j;
  step["scheme"]["step"] = "2";
  step["checksum"] = RunStateChecksum(step);
  EXPECT_THAT(ErrorOf([&] { RunStateFromJson(step, "s.json"); }), HasSubstr("scheme.step"));
  nlohmann::json huge = j;
  huge["rows"] = 1e300;
  huge["checksum"] = RunStateChecksum(huge);
  EXPECT_THAT(ErrorOf([&] { RunStateFromJson(huge, "s.json"); }), HasSubstr("damaged run state"));
}

TEST(RunStateFile, DamagedFilesAreConfigErrors) {
  const auto dir = test_support::FreshTempDir("run_state_file");
  const std::string path = (dir / "k.state.json").string();
  SaveRunState(path, ExampleState());
  EXPECT_EQ(LoadRunState(path).rows, 3);
  const std::string text = test_support::ReadText(path);
  test_support::WriteText(path, text.substr(0, text.size() / 2));
  EXPECT_THAT(ErrorOf([&] { LoadRunState(path); }), HasSubstr("not valid JSON"));
  EXPECT_THAT(ErrorOf([&] { LoadRunState((dir / "none.json").string()); }),
              HasSubstr("cannot read the run state"));
}

TEST(RunStateAgainstJournal, AcceptsItsJournalAndTheCrashWindow) {
  const auto dir = test_support::FreshTempDir("run_state_journal");
  const std::string csv = (dir / "k.csv").string();
  // The committed row on disk, and a partial line after it (a crash mid-write).
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1 + kRow2 + "0.003,1");
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(ExampleState(), csv));
  // Killed between the state and its row: resume writes the row from the state.
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1);
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(ExampleState(), csv));
  // Rows after the committed one (a stop's uncommitted row) are cut by resume, not refused.
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1 + kRow2 +
                                   "0.003,9e-06,0.006,nan,nan,nan,nan,nan\n");
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(ExampleState(), csv));
}

TEST(RunStateAgainstJournal, RefusesAJournalThatIsNotItsOwn) {
  const auto dir = test_support::FreshTempDir("run_state_other");
  const std::string csv = (dir / "k.csv").string();
  // Rows lost: the journal is shorter than it was when the state was saved.
  test_support::WriteText(csv, std::string(kHeader) + kRow0);
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(ExampleState(), csv); }),
              HasSubstr("the journal has 1 rows, but held 2"));
  // Another run's row 1.
  test_support::WriteText(csv, std::string(kHeader) + kRow0 +
                                   "0.001,2e-06,0.002,nan,0.020001,0.020001,-0.0072,1.25\n");
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(ExampleState(), csv); }),
              HasSubstr("its row 1 is"));
  // The committed row differs in its command (the one value that moves steel).
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1 +
                                   "0.002,4.0000000000000002e-06,0.004,-0.0288,0.039,0.020004,"
                                   "-0.0288,2.5\n");
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(ExampleState(), csv); }),
              HasSubstr("the committed row 2 is"));
  // Nothing was changed by the refusals.
  EXPECT_EQ(ReadJournalRows(csv, {}).complete, 3);
}

// A state's JSON edited and given a recomputed checksum (SHA-256 is unkeyed: anyone can).
nlohmann::json Forged(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = ToJson(ExampleState());
  edit(j);
  j["checksum"] = RunStateChecksum(j);
  return j;
}

TEST(RunStateItself, RefusesForgedCountersEvenWithARecomputedChecksum) {
  auto error = [](const std::function<void(nlohmann::json&)>& edit) {
    return ErrorOf([&] { RunStateFromJson(Forged(edit), "k.state.json"); });
  };
  // The unedited state passes, so every refusal below comes from its edit.
  EXPECT_EQ(error([](nlohmann::json&) {}), "(no error)");
  for (const long k : {1L, 5L, 5000L}) {
    EXPECT_THAT(error([&](nlohmann::json& j) { j["scheme"]["step"] = 2 + k; }),
                HasSubstr("rows = 3 but scheme.step = " + std::to_string(2 + k)));
    EXPECT_THAT(error([&](nlohmann::json& j) { j["scheme"]["step"] = 2 - k; }),
                HasSubstr("k.state.json: damaged run state"));
  }
  EXPECT_THAT(error([](nlohmann::json& j) { j["statistics"]["steps"] = -4; }),
              HasSubstr("statistics.steps = -4: expected a count >= 0"));
  EXPECT_THAT(error([](nlohmann::json& j) { j["statistics"]["physical_evaluations"] = -1; }),
              HasSubstr("statistics.physical_evaluations = -1"));
  EXPECT_THAT(error([](nlohmann::json& j) { j["statistics"]["steps"] = 7; }),
              HasSubstr("statistics.steps = 7 is ahead of scheme.step = 2"));
  EXPECT_THAT(error([](nlohmann::json& j) { j["statistics"]["wall_time_s"] = -1.0; }),
              HasSubstr("statistics.wall_time_s = -1.0: expected a time >= 0 s"));
  EXPECT_THAT(error([](nlohmann::json& j) { j["stage_rows"] = -1; }),
              HasSubstr("stage_rows = -1"));
  EXPECT_THAT(error([](nlohmann::json& j) {
                j["substructures"][0]["state"]["evaluations"] = -9;
              }),
              HasSubstr("substructure 'r1': evaluations = -9"));
  // t that is not the committed row's t (the row is what the journal is checked against).
  EXPECT_THAT(error([](nlohmann::json& j) { j["scheme"]["t"] = 0.005; }),
              HasSubstr("is not its row"));
  EXPECT_THAT(error([](nlohmann::json& j) { j["scheme"]["t"] = -0.002; }),
              HasSubstr("scheme.t = -0.002"));
}

TEST(RunStateAgainstJournal, RefusesAnOlderGenuineStateOfAPhysicalRun) {
  const auto dir = test_support::FreshTempDir("run_state_older");
  const std::string csv = (dir / "k.csv").string();
  // The state of row 2, then the run went on and committed row 3: that state is not the last.
  const std::string row3 = "0.003,9e-06,0.006,-0.0648,0.020009,0.020009,-0.0648,3.75\n";
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1 + kRow2 + row3);
  const std::string before = test_support::ReadText(csv);
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(ExampleState(), csv); }),
              testing::AllOf(HasSubstr("is older than the journal"),
                             HasSubstr("1 committed row after it, the last being row 3"),
                             HasSubstr("on the specimen"), HasSubstr("nothing was changed")));
  EXPECT_EQ(test_support::ReadText(csv), before);
  // A state forged one step back, consistent with the journal's row 1 and its checksum
  // recomputed: older than the journal as well.
  RunState back = ExampleState();
  back.rows = 2;
  back.scheme["step"] = 1;
  back.scheme["t"] = 0.001;
  back.scheme["x"] = {1e-06, 0.002};
  back.scheme["r"] = {nullptr};
  back.substructures[0]["state"]["last"] = {{"command_m", 0.020001}, {"position_m", 0.020001},
                                            {"force_N", -0.0072}, {"lab_time_s", 1.25}};
  back.row = {0.001, 1e-06, 0.002, kNaN, 0.020001, 0.020001, -0.0072, 1.25};
  back.journal_rows = 1;
  back.journal_last_row = std::vector<double>{0, 0, 0, 0, 0.02, 0.02, 0, 0};
  const RunState loaded = RunStateFromJson(ToJson(back), "k.state.json");
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(loaded, csv); }),
              HasSubstr("2 committed rows after it, the last being row 3"));
}

TEST(RunStateAgainstJournal, AFixedStepStatesTimeIsStepTimesH) {
  const auto dir = test_support::FreshTempDir("run_state_time");
  const std::string csv = (dir / "k.csv").string();
  // A journal and state that agree with each other, at t = 0.0025 for step 2 of h = 1 ms.
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + kRow1 +
                                   "0.0025,4.0000000000000002e-06,0.004,-0.0288,0.020004,"
                                   "0.020004,-0.0288,2.5\n");
  RunState s = ExampleState();
  s.scheme["t"] = 0.0025;
  s.row[0] = 0.0025;
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(RunStateFromJson(ToJson(s), "k"), csv); }),
              HasSubstr("its step 2 and time t = 0.0025 s disagree"));
}

TEST(RunStateAgainstJournal, CountsTheCommittedRowsOfAMultiRateRun) {
  const auto dir = test_support::FreshTempDir("run_state_mros");
  const std::string csv = (dir / "k.csv").string();
  // MR-OS: row 1 is an intermediate substep (no specimen sample), row 2 commits step 1.
  const std::string sub = "0.001,1e-06,0.002,-0.0072,nan,nan,nan,nan\n";
  test_support::WriteText(csv, std::string(kHeader) + kRow0 + sub + kRow2);
  RunState s = ExampleState();
  s.scheme["scheme"] = "mr-os";
  s.scheme["step"] = 1;
  s.journal_last_row = std::vector<double>{0.001, 1e-06, 0.002, -0.0072, kNaN, kNaN, kNaN, kNaN};
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(RunStateFromJson(ToJson(s), "k"), csv));
  // The same rows claimed as step 2 (forged, checksum recomputed): two committed rows only.
  s.scheme["step"] = 2;
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(RunStateFromJson(ToJson(s), "k"), csv); }),
              HasSubstr("it says step 2, but the journal's rows 0 to 2 hold 2 committed"));
}

TEST(RunStateAgainstJournal, ANumericalStateMayLagByLessThanTwoSaveIntervals) {
  const auto dir = test_support::FreshTempDir("run_state_numerical");
  const std::string csv = (dir / "k.csv").string();
  auto journal = [&](long rows) {
    std::string text = "t,q1,u1,r1\n";
    for (long i = 0; i < rows; ++i) text += fmt::format("{},0,0,0\n", i);
    test_support::WriteText(csv, text);
  };
  RunState s;
  s.rows = 1;
  s.scheme = {{"scheme", "runge-kutta"}, {"step", 0}, {"t", 0.0}, {"x", {0.0, 0.0}},
              {"r", {0.0}}, {"own", nullptr}};
  s.substructures = nlohmann::json::array({{{"slot", "r1"}, {"state", nlohmann::json::object()}}});
  s.row = {0, 0, 0, 0};
  const RunState loaded = RunStateFromJson(ToJson(s), "k");
  journal(1500);
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(loaded, csv));
  journal(2001);
  EXPECT_THAT(ErrorOf([&] { VerifyRunStateAgainstJournal(loaded, csv); }),
              HasSubstr("a numerical run saves its state every 1000 rows"));
}

}  // namespace
}  // namespace hybridtest::runner
