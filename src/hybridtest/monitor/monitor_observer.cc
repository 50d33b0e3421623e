// See monitor_observer.h.
#include "hybridtest/monitor/monitor_observer.h"

#include "hybridtest/monitor/background_thread.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>

namespace hybridtest::monitor {

void DescribeRun(const runner::Session& session, RunIdentity& identity, FrameLayout& layout,
                 std::vector<ActuatorInfo>& actuators) {
  const io::RunSpec& spec = session.spec();
  identity.config = spec.source.config_path;
  identity.model = spec.model.name;
  if (spec.source.test.is_object() && spec.source.test.contains("specimen")) {
    const auto& s = spec.source.test["specimen"];
    identity.specimen = s.is_string() ? s.get<std::string>() : s.dump();
  }
  identity.command = spec.output.command;
  identity.csv = spec.output.files ? spec.output.csv_path : "";
  identity.end_time = spec.scheme.duration;
  identity.slots.clear();
  actuators.clear();
  std::string bench;
  for (const auto& sub : spec.substructures) {
    identity.slots.push_back(sub.slot);
    if (!sub.is_physical()) continue;
    ActuatorInfo info{sub.slot, std::nullopt, 0.0};
    std::string type = "custom";
    if (sub.physical) {
      info.limits = sub.physical->limits;
      info.p0 = sub.physical->setup.p0;
      type = sub.physical->transfer.type;
    }
    actuators.push_back(info);
    bench += (bench.empty() ? "" : ", ") + sub.slot + ": " + type;
  }
  identity.bench = bench.empty() ? "none (numerical)" : bench;
  layout.slots = static_cast<int>(spec.substructures.size());
  layout.actuators = static_cast<int>(actuators.size());
}

MonitorObserver::MonitorObserver(MonitorState& state, MonitorObserverOptions options)
    : state_(state), options_(options) {}

MonitorObserver::~MonitorObserver() { StopCollector(); }

void MonitorObserver::OnStart(const runner::Session& session) {
  session_ = &session;
  RunIdentity identity;
  std::vector<ActuatorInfo> actuators;
  DescribeRun(session, identity, layout_, actuators);
  state_.SetIdentity(std::move(identity), layout_, std::move(actuators));
  ring_ = std::make_unique<FrameRing>(options_.ring_capacity, layout_.width());
  last_d_.assign(static_cast<std::size_t>(layout_.slots), std::nan(""));
  // On a real-time run the collector stays off the stepping thread's core and time
  // (background_thread.h); it would otherwise inherit the stepping thread's SCHED_FIFO.
  const io::RealTimeSpec& rt = session.spec().real_time;
  if (!collector_.joinable()) {
    collector_ = std::thread([this, background = rt.enabled, cpu = rt.cpu] {
      if (background) MoveThisThreadToBackground(cpu);
      Collect();
    });
  }
}

void MonitorObserver::OnTrial(const runner::TrialEvent& event) {
  if (event.at.stage != 0) return;
  const std::size_t m = std::min(event.d.size(), last_d_.size());
  for (std::size_t s = 0; s < m; ++s) last_d_[s] = event.d[s];
}

void MonitorObserver::OnCommit(const runner::CommitEvent& event) {
  if (event.kind != runner::RowKind::kCommitted || !ring_) return;
  double* f = ring_->Begin();
  if (f == nullptr) return;  // full: dropped, counted
  const runner::RunStatistics& s = session_->statistics();
  f[0] = static_cast<double>(event.step);
  f[1] = event.t;
  f[2] = s.wall_time;
  f[3] = s.lab_time;
  f[4] = static_cast<double>(s.physical_evaluations);
  const int m = layout_.slots;
  for (int i = 0; i < m; ++i) {
    f[layout_.d(i)] = last_d_[std::size_t(i)];
    f[layout_.r(i)] = i < int(event.r.size()) ? event.r[std::size_t(i)] : std::nan("");
  }
  // The journal row: t, x, r, then per physical slot command, position, force, lab time.
  const std::size_t physical = 1 + event.x.size() + event.r.size();
  for (int a = 0; a < layout_.actuators; ++a) {
    const std::size_t c = physical + 4 * std::size_t(a);
    const bool has = c + 2 < event.row.size();
    f[layout_.command(a)] = has ? event.row[c] : std::nan("");
    f[layout_.position(a)] = has ? event.row[c + 1] : std::nan("");
    f[layout_.force(a)] = has ? event.row[c + 2] : std::nan("");
  }
  ring_->Commit();
}

void MonitorObserver::OnResume(const runner::ResumeEvent& event) {
  if (event.phase == runner::ResumeEvent::kRestored && !event.row.empty()) {
    state_.AddResume(event.row[0]);
  }
}

void MonitorObserver::OnStop(const runner::StopEvent& event) {
  StopCollector();
  DrainNow();
  if (event.status == runner::SessionStatus::kFinished) {
    state_.SetStatus("finished");
    return;
  }
  std::string resume;
  const std::string csv = session_ != nullptr && session_->spec().output.files
                              ? session_->spec().output.csv_path
                              : "";
  if (!csv.empty()) {
    const bool safety = event.statistics.contains("stop") &&
                        event.statistics["stop"].value("kind", "") == "safety";
    resume = fmt::format("hybridtest resume {}{}", csv, safety ? " --after-safety-stop" : "");
  }
  state_.SetStatus("stopped", event.reason, resume);
}

void MonitorObserver::DrainNow() {
  if (!ring_) return;
  const std::size_t width = ring_->width();
  ring_->Drain([&](const double* f) { state_.AddFrame({f, width}); });
  state_.SetDropped(ring_->dropped());
}

void MonitorObserver::Collect() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, std::chrono::duration<double>(options_.drain_interval));
    if (stop_) break;
    DrainNow();
  }
}

void MonitorObserver::StopCollector() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (collector_.joinable()) collector_.join();
}

}  // namespace hybridtest::monitor
