// RunState: the checksum, the agreement of its parts, and its check against the journal
// (run_state.h; docs/safety.md, "Resuming a run").
#include "hybridtest/runner/run_state.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace hybridtest::runner
