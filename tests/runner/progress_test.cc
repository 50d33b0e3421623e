// Progress: plain lines without a terminal, the bar, quiet mode, rate limiting, ETA.
#include "hybridtest/runner/progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace hybridtest::runner {
namespace {

// A FILE* writing into memory, read back with text().
class Capture {
 public:
  Capture() : stream_(open_memstream(&buffer_, &size_)) {}
  ~Capture() {
    std::fclose(stream_);
    std::free(buffer_);
  }
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  std::FILE* stream() { return stream_; }
  std::string text() {
    std::fflush(stream_);
    return std::string(buffer_, size_);
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* stream_;
};

// A run of 10 s simulated time, 10000 steps, 2 physical evaluations per step, 1.13 s of lab
// time per evaluation, and 0.01 s of wall time per step.
ProgressSample SampleAt(long step) {
  ProgressSample s;
  s.step = step;
  s.total_steps = 10000;
  s.sim_time = 1e-3 * static_cast<double>(step);
  s.end_time = 10.0;
  s.physical_evaluations = 2 * step;
  s.lab_time = 1.13 * static_cast<double>(s.physical_evaluations);
  s.wall_time = 0.01 * static_cast<double>(step);
  return s;
}

int CountLines(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

TEST(Progress, AutoModeWithoutTerminalPrintsPeriodicLines) {
  Capture capture;
  Progress progress({.stream = capture.stream(), .line_interval = 10.0});
  EXPECT_EQ(progress.mode(), ProgressMode::kLines);  // a memory stream is not a terminal
  for (long step = 1; step <= 10000; ++step) progress.Update(SampleAt(step));
  // 100 s of wall time at one line per 10 s.
  const std::string before_finish = capture.text();
  EXPECT_EQ(CountLines(before_finish), 10) << before_finish;
  EXPECT_EQ(before_finish.find('\r'), std::string::npos);
  // The first line is drawn at 10 s: 10 % done, 90 s to go.
  const std::string first = before_finish.substr(0, before_finish.find('\n'));
  EXPECT_NE(first.find(" 10.0%"), std::string::npos) << first;
  EXPECT_NE(first.find("t 1.000/10.000 s"), std::string::npos) << first;
  EXPECT_NE(first.find("step 1000/10000"), std::string::npos) << first;
  EXPECT_NE(first.find("physical evaluations 2000"), std::string::npos) << first;
  EXPECT_NE(first.find("lab time 37m40s"), std::string::npos) << first;  // 2260 s
  EXPECT_NE(first.find("elapsed 10s"), std::string::npos) << first;
  EXPECT_NE(first.find("ETA 1m30s"), std::string::npos) << first;
  progress.Finish();
  progress.Finish();  // idempotent
  const std::string all = capture.text();
  EXPECT_EQ(CountLines(all), 11);
  EXPECT_NE(all.rfind("100.0%"), std::string::npos);
  EXPECT_NE(all.rfind("| done\n"), std::string::npos) << all;
}

TEST(Progress, QuietPrintsNothing) {
  Capture capture;
  Progress progress({.stream = capture.stream(), .mode = ProgressMode::kQuiet});
  for (long step = 1; step <= 10000; ++step) progress.Update(SampleAt(step));
  progress.Finish();
  EXPECT_EQ(capture.text(), "");
}

TEST(Progress, ShortRunStaysSilentUntilFinish) {
  Capture capture;
  Progress progress({.stream = capture.stream(), .mode = ProgressMode::kLines});
  for (long step = 1; step <= 100; ++step) progress.Update(SampleAt(step));  // 1 s of wall time
  EXPECT_EQ(capture.text(), "");
  progress.Finish();
  EXPECT_EQ(CountLines(capture.text()), 1);
  Capture unused;
  Progress never({.stream = unused.stream(), .mode = ProgressMode::kLines});
  never.Finish();
  EXPECT_EQ(unused.text(), "");
}

// Issue 50: a failed run's last line said "done".
TEST(Progress, AFailedRunEndsWithItsFailureNotDone) {
  Capture capture;
  Progress progress({.stream = capture.stream(), .mode = ProgressMode::kLines});
  for (long step = 1; step <= 100; ++step) progress.Update(SampleAt(step));
  progress.Finish("stopped: slot 1: force 12 kN beyond force_hard");
  const std::string text = capture.text();
  EXPECT_NE(text.find("| stopped: slot 1: force 12 kN beyond force_hard\n"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("done"), std::string::npos) << text;
}

TEST(Progress, BarRedrawsInPlaceAndIsRateLimited) {
  Capture capture;
  Progress progress({.stream = capture.stream(), .mode = ProgressMode::kBar,
                     .bar_interval = 1.0, .bar_width = 10});
  for (long step = 1; step <= 10000; ++step) progress.Update(SampleAt(step));
  const std::string drawn = capture.text();
  int redraws = 0;
  for (const char c : drawn) redraws += c == '\r';
  EXPECT_EQ(redraws, 100);  // 100 s of wall time, one redraw per second, not one per step
  EXPECT_EQ(CountLines(drawn), 0);
  EXPECT_NE(drawn.find("\r[#####.....]  50.0%"), std::string::npos);
  progress.Finish();
  const std::string all = capture.text();
  EXPECT_EQ(all.back(), '\n');
  EXPECT_NE(all.find("\r[##########] 100.0%"), std::string::npos);
}

TEST(Progress, EtaExtrapolatesTheAverageRate) {
  // Half done after 50 s: 50 s to go; half done after 12 s: 12 s to go.
  EXPECT_DOUBLE_EQ(EstimateRemainingWallTime(SampleAt(5000)), 50.0);
  ProgressSample half = SampleAt(5000);
  half.wall_time = 12.0;
  EXPECT_DOUBLE_EQ(EstimateRemainingWallTime(half), 12.0);
  // By steps when the end time is unknown.
  half.end_time = 0.0;
  half.step = 2500;
  EXPECT_DOUBLE_EQ(EstimateRemainingWallTime(half), 36.0);
  // Unknown before anything is done; zero at the end.
  EXPECT_LT(EstimateRemainingWallTime(SampleAt(0)), 0.0);
  EXPECT_DOUBLE_EQ(EstimateRemainingWallTime(SampleAt(10000)), 0.0);
  // Clamped: a run past its end time is 100 % done, never negative time left.
  ProgressSample past = SampleAt(10000);
  past.sim_time = 10.5;
  EXPECT_DOUBLE_EQ(CalcProgressFraction(past), 1.0);
  EXPECT_DOUBLE_EQ(EstimateRemainingWallTime(past), 0.0);
}

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(FormatDuration(-1.0), "--");
  EXPECT_EQ(FormatDuration(0.25), "250ms");
  EXPECT_EQ(FormatDuration(0.9996), "1s");
  EXPECT_EQ(FormatDuration(42.4), "42s");
  EXPECT_EQ(FormatDuration(59.6), "1m00s");
  EXPECT_EQ(FormatDuration(725.0), "12m05s");
  EXPECT_EQ(FormatDuration(6.0 * 3600 + 16 * 60), "6h16m");
  EXPECT_EQ(FormatDuration(2 * 86400 + 4 * 3600 + 5.0), "2d04h");
}

}  // namespace
}  // namespace hybridtest::runner
