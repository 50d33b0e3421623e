#include "hybridtest/runner/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hybridtest::runner {

double CalcProgressFraction(const ProgressSample& sample) {
  double fraction = 0.0;
  if (sample.end_time > 0.0) {
    fraction = sample.sim_time / sample.end_time;
  } else if (sample.total_steps > 0) {
    fraction = static_cast<double>(sample.step) / static_cast<double>(sample.total_steps);
  }
  return std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
}

double EstimateRemainingWallTime(const ProgressSample& sample) {
  const double fraction = CalcProgressFraction(sample);
  if (fraction <= 0.0 || sample.wall_time <= 0.0) return -1.0;
  return sample.wall_time * (1.0 - fraction) / fraction;
}

std::string FormatDuration(double seconds) {
  if (!(seconds >= 0.0)) return "--";
  if (std::lround(seconds * 1000.0) < 1000) return fmt::format("{}ms", std::lround(seconds * 1000.0));
  const long total = std::lround(seconds);
  if (total < 60) return fmt::format("{}s", total);
  if (total < 3600) return fmt::format("{}m{:02}s", total / 60, total % 60);
  if (total < 86400) return fmt::format("{}h{:02}m", total / 3600, (total % 3600) / 60);
  return fmt::format("{}d{:02}h", total / 86400, (total % 86400) / 3600);
}

Progress::Progress(ProgressOptions options)
    : options_(options),
      mode_(options.mode),
      next_draw_time_(std::numeric_limits<double>::infinity()) {
  if (options_.stream == nullptr) mode_ = ProgressMode::kQuiet;
  if (mode_ == ProgressMode::kAuto) {
    mode_ = ::isatty(::fileno(options_.stream)) ? ProgressMode::kBar : ProgressMode::kLines;
  }
  if (mode_ == ProgressMode::kBar) next_draw_time_ = options_.bar_interval;
  if (mode_ == ProgressMode::kLines) next_draw_time_ = options_.line_interval;
}

void Progress::Finish(std::string_view outcome) {
  if (finished_ || !has_sample_ || mode_ == ProgressMode::kQuiet) return;
  Draw(true, outcome);
  finished_ = true;
}

void Progress::Draw(bool final, std::string_view outcome) {
  if (mode_ == ProgressMode::kQuiet) return;
  const ProgressSample& s = last_;
  const double fraction = CalcProgressFraction(s);
  const std::string eta = final ? std::string(outcome) : "ETA " + FormatDuration(EstimateRemainingWallTime(s));
  const std::string steps = s.total_steps > 0 ? fmt::format("{}/{}", s.step, s.total_steps)
                                              : fmt::format("{}", s.step);
  if (mode_ == ProgressMode::kBar) {
    const int width = std::max(options_.bar_width, 1);
    const int filled = static_cast<int>(fraction * width);
    // '\r' returns to the line start; "\033[K" clears what a longer previous line left.
    fmt::print(options_.stream,
               "\r[{}{}] {:5.1f}%  t {:.3f}/{:.3f} s  step {}  phys {}  lab {}  elapsed {}  {}"
               "\033[K{}",
               std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(width - filled), '.'), 100.0 * fraction,
               s.sim_time, s.end_time, steps, s.physical_evaluations, FormatDuration(s.lab_time),
               FormatDuration(s.wall_time), eta, final ? "\n" : "");
    next_draw_time_ = s.wall_time + options_.bar_interval;
  } else {
    fmt::print(options_.stream,
               "progress {:5.1f}% | t {:.3f}/{:.3f} s | step {} | physical evaluations {} | "
               "lab time {} | elapsed {} | {}\n",
               100.0 * fraction, s.sim_time, s.end_time, steps, s.physical_evaluations,
               FormatDuration(s.lab_time), FormatDuration(s.wall_time), eta);
    next_draw_time_ = s.wall_time + options_.line_interval;
  }
  std::fflush(options_.stream);
}

}  // namespace hybridtest::runner
