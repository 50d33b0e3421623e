#pragma once
// Progress: what a long run shows while it goes. It sits in the step loop, so Update() costs
// one comparison unless it is time to draw: the caller passes the wall time it already has,
// and output is rate-limited on it.
//
//   terminal (isatty):  one bar redrawn in place, e.g.
//     [##########..........]  50.0%  t 5.000/10.000 s  step 5000/10000  phys 10000
//     lab 3h08m  elapsed 12s  ETA 12s
//   no terminal:        one plain line every `line_interval` seconds of wall time, e.g.
//     progress  50.0% | t 5.000/10.000 s | step 5000/10000 | physical evaluations 10000 |
//     lab time 3h08m | elapsed 12s | ETA 12s
//   quiet:              nothing.
// Finish() draws the final state once (and ends the bar's line), ending with how the run
// ended: "done", or its failure ("stopped: <reason>") where the ETA was. Nothing is printed before
// the first interval has passed, so a short run stays silent until it finishes.
#include <cstdio>
#include <string>
#include <string_view>

namespace hybridtest::runner {

// One observation of a run's progress.
struct ProgressSample {
  long step = 0;                  // committed steps so far
  long total_steps = 0;           // steps the run will take (0 if unknown)
  double sim_time = 0.0;          // simulated time reached. Unit: [s]
  double end_time = 0.0;          // simulated time at which the run ends. Unit: [s]
  long physical_evaluations = 0;  // trials sent to physical substructures so far
  double lab_time = 0.0;          // wall time a real bench would have needed so far. Unit: [s]
  double wall_time = 0.0;         // wall time since the run started. Unit: [s]
};

enum class ProgressMode {
  kAuto,   // kBar if the stream is a terminal, else kLines
  kBar,    // one line redrawn in place with '\r'
  kLines,  // plain periodic lines (logs, CI, pipes)
  kQuiet,  // no output at all
};

struct ProgressOptions {
  std::FILE* stream = stderr;   // where to write; tests pass a memory stream
  ProgressMode mode = ProgressMode::kAuto;
  double line_interval = 10.0;  // wall time between plain lines. Unit: [s]
  double bar_interval = 0.2;    // wall time between bar redraws. Unit: [s]
  int bar_width = 24;           // characters between the brackets
};

class Progress {
 public:
  explicit Progress(ProgressOptions options = {});

  // Records a sample; draws it if the mode's interval has passed since the last drawing.
  void Update(const ProgressSample& sample) {
    last_ = sample;
    has_sample_ = true;
    if (sample.wall_time >= next_draw_time_) Draw(false);
  }

  // Draws the last sample as the final state, with `outcome` in place of the ETA ("done", or
  // "stopped: <reason>" for a run that failed). Idempotent; does nothing in quiet mode or if
  // Update() was never called.
  void Finish(std::string_view outcome = "done");

  ProgressMode mode() const { return mode_; }  // resolved: never kAuto

 private:
  void Draw(bool final, std::string_view outcome = {});

  ProgressOptions options_;
  ProgressMode mode_;
  ProgressSample last_;
  bool has_sample_ = false;
  bool finished_ = false;
  double next_draw_time_;  // wall time of the next drawing. Unit: [s]
};

// Fraction of the run done, in [0, 1]: by simulated time if end_time > 0, else by steps;
// 0 if neither is known.
double CalcProgressFraction(const ProgressSample& sample);

// Remaining wall time, extrapolated at the average rate so far. Unit: [s]. Negative if
// unknown (nothing done yet).
double EstimateRemainingWallTime(const ProgressSample& sample);

// "850ms", "42s", "12m05s", "3h08m", "2d04h"; "--" for a negative (unknown) duration.
std::string FormatDuration(double seconds);

}  // namespace hybridtest::runner
