// See paced_loop.h.
#include "hybridtest/runner/paced_loop.h"

#include <fmt/core.h>

#include <Eigen/QR>
#include <algorithm>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/actuator_setup.h"

namespace hybridtest::runner {
namespace {

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

PacedLoop::PacedLoop(Session& session, Clock& clock)
    : session_(session), clock_(clock), tick_(session.spec().scheme.dt) {
  const io::SchemeSpec& scheme = session.spec().scheme;
  if (scheme.config.kind != schemes::SchemeKind::kAlphaOs || scheme.config.adaptive.enabled) {
    throw ConfigError(fmt::format(
        "real_time: integrator.scheme = {}{}: a real-time run needs one specimen evaluation per "
        "fixed step; use `scheme: alpha-os` without `adaptive:`",
        schemes::SchemeKindName(scheme.config.kind),
        scheme.config.adaptive.enabled ? " with an adaptive step" : ""));
  }
  // Every actuator runs paced, or nothing moves.
  const auto& subs = session.substructures();
  const auto& blocks = session.slot_map().substructures;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (!blocks[b].physical) continue;
    const transfer::TransferSystem* t = subs[b]->transfer_system();
    if (t == nullptr || !t->can_run_paced()) {
      throw ConfigError(fmt::format(
          "real_time: substructures.{}: {} cannot run in real time (paced: its {} actuator(s) "
          "would settle every move in lab time); use `transfer: {{type: rt_plant, ...}}` (or a "
          "compensated one, or a remote `hybridtest bench --real-time` server) or remove the "
          "`real_time:` block", blocks[b].name, t != nullptr ? t->Describe() : subs[b]->Describe(),
          blocks[b].num_actuators));
    }
  }
  const io::RealTimeSpec& rt = session.spec().real_time;
  miss_tolerance_ = rt.miss_tolerance.value_or(0.25 * tick_);
  hold_after_ = rt.hold_after_misses;
  const auto ticks = static_cast<std::size_t>(std::max(0L, scheme.steps)) + 1;
  late_.assign(ticks, 0.0);
  compute_.assign(ticks, 0.0);
  // The criteria of every physical substructure's actuators and slots.
  std::vector<TrackingSet::Block> tracked;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (!blocks[b].physical) continue;
    TrackingSet::Block t;
    t.name = blocks[b].name;
    t.first_actuator = blocks[b].first_actuator;
    t.num_actuators = blocks[b].num_actuators;
    for (int s : blocks[b].slots) t.slots.push_back(session.slot_map().slots[std::size_t(s)].name);
    const auto m = static_cast<Eigen::Index>(t.slots.size());
    if (const substructures::ActuatorSetup* setup = subs[b]->actuator_setup()) {
      t.slot_of_actuator = setup->linearisation().completeOrthogonalDecomposition().pseudoInverse();
      t.p0 = setup->p0();
    } else {
      t.slot_of_actuator = Eigen::MatrixXd::Identity(m, t.num_actuators);
      t.p0 = Eigen::VectorXd::Zero(t.num_actuators);
    }
    tracked.push_back(std::move(t));
  }
  // The live J1 over the last second (at least 64 ticks).
  const long window = std::max(64L, static_cast<long>(std::lround(1.0 / tick_)));
  tracking_.Reserve(std::move(tracked), static_cast<long>(ticks), tick_, window);
  sample_J1_.assign(tracking_.num_actuators(), 0.0);
  sample_J2_.assign(tracking_.num_actuators(), 0.0);
  sample_J3_.assign(tracking_.num_actuators(), 0.0);
  sample_delay_.assign(tracking_.num_actuators(), 0.0);
  session.AddObserver(*this);
}

const RealTimeSample* PacedLoop::Sample() {
  RealTimeSample& s = sample_;
  s.ticks = stats_.ticks;
  s.misses = stats_.misses;
  s.misses_in_a_row = consecutive_;
  s.max_misses_in_a_row = stats_.max_consecutive_misses;
  s.overruns = stats_.overruns;
  s.late = tick_late();
  s.compute = previous_compute();
  s.J2 = criteria().J2();
  s.J3 = criteria().J3();
  for (std::size_t k = 0; k < sample_J1_.size(); ++k) {
    sample_J1_[k] = tracking_.live_J1_ms(k);
    sample_J2_[k] = tracking_.actuator(k).J2();
    sample_J3_[k] = tracking_.actuator(k).J3();
  }
  s.J1_ms = sample_J1_;
  s.actuator_J2 = sample_J2_;
  s.actuator_J3 = sample_J3_;
  // The compensators' estimates, per actuator in the run's order.
  const auto& subs = session_.substructures();
  const auto& blocks = session_.slot_map().substructures;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const transfer::TransferSystem* t = subs[b]->transfer_system();
    if (!blocks[b].physical || t == nullptr) continue;
    for (int k = 0; k < blocks[b].num_actuators; ++k) {
      const auto a = static_cast<std::size_t>(blocks[b].first_actuator + k);
      if (a < sample_delay_.size()) sample_delay_[a] = t->actuator_compensated_delay(k);
    }
  }
  s.compensated_delay_s = sample_delay_;
  return &s;
}

void PacedLoop::OnTrial(const TrialEvent& event) {
  if (!paced_ || event.exchanges.empty() || event.at.stage < 0) return;
  tracking_.Add(event.exchanges);
}

void PacedLoop::Start() {
  // Every transfer system runs paced from here (the constructor checked each can).
  auto& subs = session_.substructures();
  for (std::size_t b = 0; b < subs.size(); ++b) {
    if (!session_.slot_map().substructures[b].physical) continue;
    transfer::TransferSystem* t = subs[b]->transfer_system();
    if (t != nullptr) t->StartPaced(tick_, clock_);
  }
  paced_ = true;
  if (queue_ != nullptr) stats_.queue_min_free = queue_->capacity();
  t0_ = clock_.Now();
  k_ = 0;
  consecutive_ = 0;
}

void PacedLoop::BeforeStep(bool after_hold) {
  ++k_;
  // After an operator's hold the ticks start again one step from now.
  if (after_hold) t0_ = clock_.Now() - static_cast<double>(k_ - 1) * tick_;
  const double deadline = t0_ + static_cast<double>(k_) * tick_;
  // The wall clock sleeps short and spins the rest (common/clock.h).
  clock_.WaitUntil(deadline);
  const double late = clock_.Now() - deadline;
  // The tick counts before its step: the last step's statistics (AddStatistics, inside the
  // step that finishes the run) include it.
  i_ = static_cast<std::size_t>(stats_.ticks);
  if (i_ < late_.size()) late_[i_] = late;
  ++stats_.ticks;
  if (late > miss_tolerance_) {
    ++stats_.misses;
    ++consecutive_;
    stats_.max_consecutive_misses = std::max(stats_.max_consecutive_misses, consecutive_);
  } else {
    consecutive_ = 0;
  }
  if (queue_ != nullptr) {
    const std::size_t free = queue_->free_slots();
    stats_.queue_min_free = std::min(stats_.queue_min_free, free);
    if (free < kQueueReserve && clock_.is_virtual()) {
      // Simulated time has no deadline to miss: the loop waits for the files.
      ++stats_.queue_waits;
      queue_->WaitForFree(kQueueReserve);
    } else if (free < kQueueReserve && !stats_.held_on_queue) {
      stats_.held_on_queue = true;
      session_.RequestStop(fmt::format(
          "held: the observers' queue is nearly full ({} of {} events free): the files "
          "cannot keep up with the real-time loop (raise real_time.queue or write to a "
          "faster disk)", free, queue_->capacity()));
    }
  }
  step_start_ = std::chrono::steady_clock::now();
}

void PacedLoop::AfterStep(const StepResult& r) {
  const double compute =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start_).count();
  if (i_ < compute_.size()) compute_[i_] = compute;
  if (compute > tick_) ++stats_.overruns;
  if (stats_.ticks % kLiveJ1Every == 0) tracking_.UpdateLiveJ1();
  if (hold_after_ > 0 && consecutive_ >= hold_after_ && r.status == SessionStatus::kWorking &&
      !stats_.held_on_misses) {
    stats_.held_on_misses = true;
    session_.RequestStop(fmt::format(
        "held after {} consecutive missed deadlines (real_time.hold_after_misses; a tick later "
        "than {} s is a miss)", consecutive_, miss_tolerance_));
  }
}

void PacedLoop::Summarise() {
  const auto n = std::min(static_cast<std::size_t>(stats_.ticks), late_.size());
  const std::vector<double> late(late_.begin(), late_.begin() + static_cast<std::ptrdiff_t>(n));
  const std::vector<double> compute(compute_.begin(),
                                    compute_.begin() + static_cast<std::ptrdiff_t>(n));
  stats_.late_p50 = Percentile(late, 0.5);
  stats_.late_p99 = Percentile(late, 0.99);
  stats_.late_max = late.empty() ? 0.0 : *std::max_element(late.begin(), late.end());
  stats_.compute_p50 = Percentile(compute, 0.5);
  stats_.compute_p99 = Percentile(compute, 0.99);
  stats_.compute_max = compute.empty() ? 0.0 : *std::max_element(compute.begin(), compute.end());
}

nlohmann::json PacedLoop::ToJson() const {
  const PacedStatistics& s = stats_;
  nlohmann::json j = {{"clock", clock_.name()},
                      {"tick_s", tick_},
                      {"ticks", s.ticks},
                      {"misses", s.misses},
                      {"miss_tolerance_s", miss_tolerance_},
                      {"overruns", s.overruns},
                      {"max_consecutive_misses", s.max_consecutive_misses},
                      {"hold_after_misses", hold_after_},
                      {"held_on_misses", s.held_on_misses},
                      {"held_on_queue", s.held_on_queue},
                      {"queue_waits", s.queue_waits},
                      {"queue", queue_ != nullptr ? nlohmann::json{{"capacity", queue_->capacity()},
                                                                   {"min_free", s.queue_min_free}}
                                                  : nlohmann::json(nullptr)},
                      {"late_s", {{"p50", s.late_p50}, {"p99", s.late_p99}, {"max", s.late_max}}},
                      {"compute_s",
                       {{"p50", s.compute_p50}, {"p99", s.compute_p99}, {"max", s.compute_max}}}};
  j["setup"] = setup_notes_;
  j["stability"] = stability_;
  // The compensators' estimates (delay, amplitude) per substructure.
  nlohmann::json compensators = nlohmann::json::object();
  const auto& subs = session_.substructures();
  for (std::size_t k = 0; k < subs.size(); ++k) {
    const transfer::TransferSystem* t = subs[k]->transfer_system();
    if (t == nullptr) continue;
    if (nlohmann::json c = t->CompensationRecord(); !c.is_null()) {
      compensators[session_.slot_map().substructures[k].name] = std::move(c);
    }
  }
  if (!compensators.empty()) j["compensation"] = compensators;
  // The first actuator's J1–J3 at the top, as before there were several; then every one's.
  if (tracking_.num_actuators() > 0) j.update(tracking_.actuator(0).ToJson());
  j.update(tracking_.ToJson());
  return j;
}

void PacedLoop::AddStatistics(nlohmann::json& statistics) {
  Summarise();
  statistics["real_time"] = ToJson();
}

}  // namespace hybridtest::runner
