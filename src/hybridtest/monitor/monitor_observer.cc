// See monitor_observer.h.
#include "hybridtest/monitor/monitor_observer.h"

#include "hybridtest/monitor/background_thread.h"
#include "hybridtest/runner/run_record.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace hybridtest::monitor {

namespace {

// The physical substructures whose transfer system compensates a delay (their estimates are
// shown live on a paced run).
std::vector<int> CompensatedBlocks(const runner::StartEvent& run) {
  std::vector<int> blocks;
  const auto& map = run.slot_map.substructures;
  for (std::size_t b = 0; b < map.size(); ++b) {
    const transfer::TransferSystem* t = run.substructures[b]->transfer_system();
    if (map[b].physical && t != nullptr && !t->CompensationRecord().is_null()) {
      blocks.push_back(static_cast<int>(b));
    }
  }
  return blocks;
}

}  // namespace

void DescribeRun(const runner::StartEvent& run, RunIdentity& identity, FrameLayout& layout,
                 std::vector<ActuatorInfo>& actuators) {
  const io::RunSpec& spec = run.spec;
  const runner::SlotMap& map = run.slot_map;
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
  for (const auto& slot : map.slots) identity.slots.push_back(slot.name);
  // The actuators in the run's order, named as their journal channels are.
  std::vector<std::string> names;
  for (const io::Channel& c : runner::JournalChannels(spec)) {
    if (c.name.ends_with("_command")) names.push_back(c.name.substr(0, c.name.size() - 8));
  }
  actuators.clear();
  std::string bench;
  for (std::size_t b = 0; b < map.substructures.size(); ++b) {
    const runner::SlotMap::Block& block = map.substructures[b];
    if (!block.physical) continue;
    const substructures::Substructure& sub = *run.substructures[b];
    std::vector<std::string> slots;
    for (int s : block.slots) slots.push_back(map.slots[std::size_t(s)].name);
    for (int k = 0; k < block.num_actuators; ++k) {
      const auto a = static_cast<std::size_t>(block.first_actuator + k);
      actuators.push_back({a < names.size() ? names[a] : fmt::format("{}_a{}", block.name, k + 1),
                           block.name, k, slots, sub.actuator_limits(k), sub.actuator_p0(k)});
    }
    const auto& spec_sub = spec.substructures[b];
    bench += fmt::format("{}{}: {}{}", bench.empty() ? "" : ", ", block.name,
                         spec_sub.physical ? spec_sub.physical->transfer.type : "custom",
                         block.num_actuators > 1
                             ? fmt::format(" ({} actuators)", block.num_actuators) : "");
  }
  identity.bench = bench.empty() ? "none (numerical)" : bench;
  identity.real_time = {};
  if (spec.real_time.enabled) {
    identity.real_time = {true, "", spec.scheme.dt, spec.real_time.hold_after_misses, {}, {}};
    for (int b : CompensatedBlocks(run)) {
      const runner::SlotMap::Block& block = map.substructures[std::size_t(b)];
      monitor::CompensatedBlock entry{block.name, {}};
      for (int k = 0; k < block.num_actuators; ++k) {
        entry.actuators.push_back(actuators[std::size_t(block.first_actuator + k)].name);
      }
      identity.real_time.compensators.push_back(std::move(entry));
    }
    for (const ActuatorInfo& a : actuators) identity.real_time.actuators.push_back(a.name);
  }
  layout.slots = static_cast<int>(map.slots.size());
  layout.actuators = static_cast<int>(actuators.size());
}

MonitorObserver::MonitorObserver(MonitorState& state, MonitorObserverOptions options)
    : state_(state), options_(options) {}

MonitorObserver::~MonitorObserver() { StopCollector(); }

void MonitorObserver::OnStart(const runner::StartEvent& run) {
  csv_ = run.spec.output.files ? run.spec.output.csv_path : "";
  RunIdentity identity;
  std::vector<ActuatorInfo> actuators;
  DescribeRun(run, identity, layout_, actuators);
  identity.real_time.clock = run.clock;
  compensated_.clear();
  for (int b : CompensatedBlocks(run)) {
    const runner::SlotMap::Block& block = run.slot_map.substructures[std::size_t(b)];
    for (int k = 0; k < block.num_actuators; ++k) {
      compensated_.push_back(static_cast<std::size_t>(block.first_actuator + k));
    }
  }
  layout_ = state_.SetIdentity(std::move(identity), layout_, std::move(actuators));
  ring_ = std::make_unique<runner::SpscRing<std::vector<double>>>(
      std::max<std::size_t>(options_.ring_capacity, 1),
      [width = layout_.width()] { return std::vector<double>(width); });
  dropped_.store(0, std::memory_order_relaxed);
  last_d_.assign(static_cast<std::size_t>(layout_.slots), std::nan(""));
  // On a real-time run the collector stays off the stepping thread's core and time
  // (background_thread.h); it would otherwise inherit the stepping thread's SCHED_FIFO.
  const io::RealTimeSpec& rt = run.spec.real_time;
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
  std::vector<double>* frame = ring_->Claim();
  if (frame == nullptr) {  // full: dropped, counted
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  double* f = frame->data();
  const runner::RunStatistics& s = event.statistics;
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
  if (layout_.real_time > 0) FillRealTime(event.real_time, f + layout_.rt(0));
  ring_->Publish();
}

void MonitorObserver::FillRealTime(const runner::RealTimeSample* sample, double* c) const {
  std::fill(c, c + layout_.real_time, std::nan(""));
  if (sample == nullptr) return;
  const runner::RealTimeSample& s = *sample;
  c[kRtTicks] = static_cast<double>(s.ticks);
  c[kRtMisses] = static_cast<double>(s.misses);
  c[kRtMissesInARow] = static_cast<double>(s.misses_in_a_row);
  c[kRtMaxInARow] = static_cast<double>(s.max_misses_in_a_row);
  c[kRtOverruns] = static_cast<double>(s.overruns);
  c[kRtLate] = s.late;
  c[kRtCompute] = s.compute;
  c[kRtJ2] = s.J2;
  c[kRtJ3] = s.J3;
  std::size_t first = kRtColumns;  // one delay per compensated actuator
  for (const std::size_t a : compensated_) {
    if (first >= layout_.real_time) break;
    c[first++] = a < s.compensated_delay_s.size() ? s.compensated_delay_s[a] : std::nan("");
  }
  for (std::size_t k = 0; k < s.J1_ms.size() && first + 3 * k + 2 < layout_.real_time; ++k) {
    c[first + 3 * k] = s.J1_ms[k];
    c[first + 3 * k + 1] = s.actuator_J2[k];
    c[first + 3 * k + 2] = s.actuator_J3[k];
  }
}

void MonitorObserver::OnResume(const runner::ResumeEvent& event) {
  if (event.phase == runner::ResumeEvent::kRestored && !event.row.empty()) {
    state_.AddResume(event.row[0]);
  }
}

void MonitorObserver::OnStop(const runner::StopEvent& event) {
  StopCollector();
  DrainNow();
  if (event.statistics.contains("real_time")) state_.SetRealTime(event.statistics["real_time"]);
  if (event.status == runner::SessionStatus::kFinished) {
    state_.SetStatus("finished");
    return;
  }
  std::string resume;
  const std::string& csv = csv_;
  if (!csv.empty()) {
    const bool safety = event.statistics.contains("stop") &&
                        event.statistics["stop"].value("kind", "") == "safety";
    resume = fmt::format("hybridtest resume {}{}", csv, safety ? " --after-safety-stop" : "");
  }
  state_.SetStatus("stopped", event.reason, resume);
}

void MonitorObserver::DrainNow() {
  if (!ring_) return;
  while (const std::vector<double>* f = ring_->Front()) {
    state_.AddFrame({f->data(), f->size()});
    ring_->Pop();
  }
  state_.SetDropped(dropped());
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
