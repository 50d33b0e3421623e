#pragma once
// RunFollower: feeds a MonitorState from a run's files, read-only: `hybridtest monitor RUN.csv`
// follows a run started elsewhere (another process, another user) and serves a finished one.
//
// Each Poll() reads what was appended to the journal since the last one (whole lines only),
// the sidecar (identity, status, stop reason, resumes, operator actions) and counts the stage
// record's new rows (the physical evaluations). The journal has no slot displacement: d is
// null for a followed run; the meters' limits come from the config kept in the sidecar
// (substructures.SLOT.safety). "step" is the journal's row index. A frame's wall time is the
// follower's own clock, for the ETA.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "hybridtest/monitor/monitor_state.h"

namespace hybridtest::monitor {

class RunFollower {
 public:
  // Throws IoError if the journal or its sidecar cannot be read.
  RunFollower(std::string csv_path, MonitorState& state);

  // Reads what is new. Returns true while the run may still change (its sidecar says
  // "running"). Throws IoError if a file disappears or stops making sense.
  bool Poll();

 private:
  void ReadSidecar();
  void ReadRows();
  void CountStages();

  std::string csv_;
  MonitorState& state_;
  std::chrono::steady_clock::time_point start_;
  bool described_ = false;
  std::uintmax_t offset_ = 0, stages_offset_ = 0;
  std::string partial_;
  long rows_ = 0, evaluations_ = 0;
  bool header_read_ = false;
  FrameLayout layout_;
  std::vector<int> r_col_, cmd_col_, lab_col_;  // journal columns of r, command, lab time
  std::vector<double> frame_;
  std::size_t resumes_seen_ = 0, actions_seen_ = 0;
  std::string status_;
};

}  // namespace hybridtest::monitor
