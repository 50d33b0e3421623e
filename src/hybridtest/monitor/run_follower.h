#pragma once
// RunFollower: feeds a MonitorState from a run's files, read-only: `hybridtest monitor RUN.csv`
// follows a run started elsewhere (another process, another user) and serves a finished one.
//
// Each Poll() reads what was appended to the journal since the last one (whole lines only),
// the sidecar (identity, status, stop reason, resumes, operator actions) and counts the stage
// record's new rows (the physical evaluations). The journal has no slot displacement: d is
// null for a followed run. Every actuator of every physical substructure has its meters, named
// by its journal channels (the sidecar's substructures[].channels); its limits and p0 come
// from the config kept in the sidecar (report::FindActuatorLimits: a list holds one value per
// actuator; setup.p0). "step" is the journal's row index. A frame's wall time is the time
// since the sidecar's start_time (the follower's own clock if it has none), for the ETA; once
// the run has ended, its elapsed and lab time, evaluations and real-time statistics are the
// ones its sidecar records.
#include <chrono>
#include <cstdint>
#include <optional>
#include <utility>
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
  void Describe(const nlohmann::json& sidecar);  // identity, actuators, layout
  void ReadRows();
  void CountStages();
  double Elapsed() const;  // [s] since the run started

  std::string csv_;
  MonitorState& state_;
  std::chrono::steady_clock::time_point start_;
  bool described_ = false;
  std::uintmax_t offset_ = 0, stages_offset_ = 0;
  std::string partial_;
  long rows_ = 0, evaluations_ = 0;
  bool header_read_ = false;
  FrameLayout layout_;
  std::vector<std::pair<std::string, std::string>> channels_;  // per actuator: command, lab time
  std::vector<int> r_col_, cmd_col_, lab_col_;  // journal columns of r, command, lab time
  std::optional<double> started_;               // the run's start_time [s since the epoch]
  std::vector<double> frame_;
  std::size_t resumes_seen_ = 0, actions_seen_ = 0;
  std::string status_;
};

}  // namespace hybridtest::monitor
