#pragma once
// MonitorState: what the monitor's page shows about one run, shared between the side that
// feeds it (the live observer's collector thread, or the follower of a journal) and the HTTP
// server's threads, behind one mutex. The stepping thread of a run never touches it (it
// writes frames into a runner::SpscRing; see monitor_observer.h).
//
// A frame is one committed row, flat (FrameLayout): step, t [s], wall time [s], lab time [s],
// physical evaluations, then d [m] and r [N] per model slot, then command, position [m] and
// force [N] per actuator of every physical substructure (the run's actuator order: the
// journal's channel groups), then, on a paced run, the real-time columns (real_time_panel.h).
// The history keeps at most `history_capacity` frames of the whole
// run: when full, every other frame is dropped and only every 2nd (4th, ...) frame is kept
// from then on, so a long run is shown whole at a bounded cost.
//
// Status: "starting" → "running" ⇄ "holding" → "stopped" | "finished".
//
// Viewers share one snapshot: StateBody() and SeriesBody() return the serialized answer of
// /api/state and /api/series, built at most once per change of the state and at most once
// per `kBodyInterval` (so at most 1/kBodyInterval builds per second whatever the number of
// viewers), and handed to every viewer that asks until the next build. Building takes the
// state's mutex only to copy what it reads into the JSON value; the text is written outside
// it, so the collector (which feeds the state) never waits for a serialization.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/monitor/real_time_panel.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::monitor {

struct FrameLayout {
  int slots = 0;      // the model's restoring-force slots m
  int actuators = 0;  // actuators of every physical substructure n
  std::size_t real_time = 0;  // real-time columns (RealTimePanel::columns(); 0: not paced)
  static constexpr int kHead = 5;  // step, t, wall, lab, evaluations
  std::size_t width() const { return rt(0) + real_time; }
  std::size_t d(int s) const { return kHead + std::size_t(s); }
  std::size_t r(int s) const { return kHead + std::size_t(slots + s); }
  std::size_t command(int a) const { return kHead + 2 * std::size_t(slots) + 3 * std::size_t(a); }
  std::size_t position(int a) const { return command(a) + 1; }
  std::size_t force(int a) const { return command(a) + 2; }
  std::size_t rt(int c) const {
    return kHead + 2 * std::size_t(slots) + 3 * std::size_t(actuators) + std::size_t(c);
  }
};

// One actuator of a physical substructure as its meter group, scopes and loop show it.
struct ActuatorInfo {
  std::string name;                 // its journal channels' prefix: "r1", "blade1_a2"
  std::string substructure;         // the physical substructure it belongs to (config key)
  int index = 0;                    // its place among that substructure's actuators (0-based)
  std::vector<std::string> slots;   // the model slots its substructure serves
  std::optional<transfer::SafetyLimits> limits;  // the runner's limits, SI (if known)
  std::optional<double> p0;         // zero-force actuator position [m] (if known)
};

// Who and what the run is.
struct RunIdentity {
  std::string config;    // the run config's path
  std::string model;     // model name
  std::string specimen;  // the config's test.specimen, if given
  std::string bench;     // the physical slots' transfer types, e.g. "r1: emulated"
  std::string command;   // "run", "simulate", ...
  std::string csv;       // the journal
  std::vector<std::string> slots;  // the model's slot names
  double end_time = 0.0;           // simulated time at which the run ends [s]
  std::string mode = "live";       // "live" (a run's own monitor) or "follow" (a journal)
  RealTimeSetup real_time;         // a paced run's setting (enabled: the frames' rt columns)
};

// What a run's own record says of it once it has ended (a followed journal's sidecar, a live
// run's stop): shown instead of what the frames add up to.
struct RecordedTotals {
  std::optional<double> wall_time;  // [s] elapsed, as recorded
  std::optional<double> lab_time;   // [s]
  std::optional<long> physical_evaluations;
};

// Near a limit: the fraction of a limit used at which a meter turns from normal to near.
inline constexpr double kNearFraction = 0.8;

// Margin of one actuator against its limits: "normal", "near" or "tripped"; fractions in
// [0, ∞): force |F|/force_hard, stroke |pos − mid|/half-range.
struct Margin {
  double force_fraction = 0.0;
  double stroke_fraction = 0.0;
  std::string level = "normal";
};
Margin CalcMargin(const transfer::SafetyLimits& limits, double position, double force);

// The monitor's JSON text (compact; invalid UTF-8 replaced).
std::string JsonText(const nlohmann::json& value);

// The shortest time between two builds of a shared answer (StateBody, SeriesBody). Unit: [s]
inline constexpr double kBodyInterval = 0.05;

class MonitorState {
 public:
  explicit MonitorState(std::size_t history_capacity = 4000);

  // Returns `layout` with its real-time columns (from identity.real_time): the frames' layout.
  FrameLayout SetIdentity(RunIdentity identity, FrameLayout layout,
                          std::vector<ActuatorInfo> actuators);
  // status: see above; reason (a stop's) and the command that continues a stopped run.
  void SetStatus(const std::string& status, const std::string& reason = "",
                 const std::string& resume_command = "");
  std::string status() const;
  void AddFrame(std::span<const double> frame);  // frame.size() == layout width
  void AddResume(double t);                      // a resume at simulated time t [s]
  void AddAction(nlohmann::json action);         // an operator action (or a refusal)
  void SetDropped(long frames);                  // frames the ring dropped so far
  void SetActionsPolicy(const std::string& policy);  // "token", "open" or "read-only"
  // A paced run's real-time record once it has ended (the sidecar's statistics.real_time).
  void SetRealTime(nlohmann::json realtime);
  void SetRecorded(const RecordedTotals& totals);

  // GET /api/state.
  nlohmann::json StateJson() const;
  // GET /api/series: the history frames after `since` (a frame sequence number), or all of
  // them if `generation` is not the current one (the history was thinned since).
  nlohmann::json SeriesJson(long since, long generation) const;
  long frames() const;  // frames received

  // The same, as text shared by every viewer (see above). Thread-safe.
  std::shared_ptr<const std::string> StateBody() const;
  std::shared_ptr<const std::string> SeriesBody(long since, long generation) const;
  long body_builds() const;  // answers built so far (for tests and the bench)

 private:
  using BodyClock = std::chrono::steady_clock;
  struct CachedBody {
    long version = -1;
    long since = 0;
    bool all = false;
    BodyClock::time_point built;
    std::shared_ptr<const std::string> text;
  };
  void Thin();  // with mutex_ held
  // The cached answer matching (since, all) if it is current, or young enough to be reused.
  static std::shared_ptr<const std::string> Cached(const std::vector<CachedBody>& cache,
                                                   long since, bool all, long version,
                                                   BodyClock::time_point now);
  static void Store(std::vector<CachedBody>& cache, CachedBody body);

  mutable std::mutex mutex_;
  std::size_t capacity_;
  RunIdentity identity_;
  FrameLayout layout_;
  std::vector<ActuatorInfo> actuators_;
  std::string status_ = "starting", reason_, resume_command_;
  std::vector<double> latest_;
  std::vector<std::vector<double>> history_;  // kept frames, each with its sequence number last
  long frames_ = 0, stride_ = 1, generation_ = 0, dropped_ = 0;
  std::vector<double> resumes_;
  nlohmann::json actions_ = nlohmann::json::array();
  std::string actions_policy_ = "token";
  RealTimePanel realtime_;
  RecordedTotals recorded_;
  // ETA: simulated time per wall second, smoothed over windows of ≥ 0.5 s of wall time.
  double rate_ = 0.0, window_t_ = 0.0, window_wall_ = -1.0;
  long version_ = 0;  // changes of anything a viewer sees (with mutex_ held)
  // The shared answers (body_mutex_: one builder at a time; never held with mutex_ waiting).
  mutable std::mutex body_mutex_;
  mutable std::vector<CachedBody> state_bodies_, series_bodies_;
  mutable long body_builds_ = 0;
};

}  // namespace hybridtest::monitor
