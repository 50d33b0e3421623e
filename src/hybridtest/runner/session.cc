// See session.h.
#include "hybridtest/runner/session.h"

#include <fmt/core.h>

#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/constraint_force_recorder.h"
#include "hybridtest/runner/pre_move_checks.h"
#include "hybridtest/runner/real_time_setup.h"
#include "hybridtest/runner/run_files.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/session_seam.h"
#include "hybridtest/runner/slot_info.h"
#include "hybridtest/runner/stop_request.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::runner {

const char* StatusName(SessionStatus status) {
  switch (status) {
    case SessionStatus::kWorking: return "working";
    case SessionStatus::kFinished: return "finished";
    case SessionStatus::kHeld: return "held";
    case SessionStatus::kStopped: return "stopped";
  }
  return "?";
}

nlohmann::json ToJson(const RunStatistics& s) {
  return {{"steps", s.steps},           {"rows", s.rows},
          {"physical_evaluations", s.physical_evaluations},
          {"sim_time_s", s.sim_time},   {"wall_time_s", s.wall_time},
          {"lab_time_s", s.lab_time},   {"slowdown", s.slowdown},
          {"wall_slowdown", s.wall_slowdown}};
}

Session::Session(io::RunSpec spec, SessionOptions options)
    : Session(std::move(spec), OpenedRun{}, std::move(options)) {}

Session::Session(io::RunSpec spec, OpenedRun opened, SessionOptions options)
    : opened_(std::move(opened)), spec_(std::move(spec)), options_(std::move(options)) {
  // No run writes its files but through the front door (its lock, guards, budget, record).
  if (spec_.output.files && !(opened_.locked() && opened_.journal() == spec_.output.csv_path)) {
    throw ConfigError(fmt::format(
        "{}: a run that writes files is opened by the front door first: runner::OpenRun(spec) "
        "(a resume: OpenResume), then Session(spec, std::move(opened)){}; or set output.files "
        "= false for a run in memory", spec_.output.csv_path.empty() ? "run spec" :
        spec_.output.csv_path, opened_.locked() ? fmt::format(" (the run given was opened "
        "for {})", opened_.journal()) : ""));
  }
  io::ValidateRunSpec(spec_);
  std::vector<std::string> slot_names;
  for (const auto& s : model().slots()) slot_names.push_back(s.info.name);
  slot_of_ = substructures::SlotIndices(spec_.substructures, slot_names);
  std::vector<std::string> names;
  std::size_t actuators = 0;
  for (std::size_t s = 0; s < spec_.substructures.size(); ++s) {
    subs_.push_back(spec_.substructures[s].Build());
    if (subs_.back()->num_slots() != static_cast<int>(slot_of_[s].size())) {
      throw ConfigError(fmt::format("substructure {} serves {} slots, its config lists {}",
                                    spec_.substructures[s].slot, subs_.back()->num_slots(),
                                    slot_of_[s].size()));
    }
    if (subs_.back()->is_physical()) ++physical_count_;
    names.push_back(spec_.substructures[s].slot);
    actuators += static_cast<std::size_t>(subs_.back()->num_actuators());
  }
  slot_map_ = MakeSlotMap(subs_, names, slot_of_, slot_names);
  row_.resize(static_cast<Eigen::Index>(JournalChannels(spec_).size()));
  if (!RecordedConstraintRows(model()).empty()) {
    forces_ = std::make_unique<ConstraintForceRecorder>(model());
  }
  r0_.resize(model().num_slots());
  exchanges_.resize(actuators);
  seam_ = std::make_unique<Seam>(*this);
  rows_sink_ = std::make_unique<Rows>(*this);
  // Before anything opens or moves (pre_move_checks.h).
  if (options_.pre_move_checks) CheckBeforeMoving(spec_, subs_);
  if (spec_.output.files) {
    files_ = std::make_unique<RunFiles>(spec_, options_.resume_record);
    observers_.push_back(files_.get());
  }
  BuildPacer();
}

Session::~Session() {
  // A session dropped while working leaves every actuator holding.
  if (initialized_ && result_.status == SessionStatus::kWorking) {
    for (auto& s : subs_) s->Hold();
  }
}

void Session::AddObserver(SessionObserver& observer) {
  if (initialized_) {
    throw Error("Session::AddObserver: add observers before Initialize()");
  }
  observers_.push_back(&observer);
}

std::vector<SessionObserver*> Session::ExchangeObservers(
    std::vector<SessionObserver*> observers) {
  if (initialized_) throw Error("Session::ExchangeObservers: before Initialize()");
  observers_.swap(observers);
  return observers;
}

void Session::SetState(const RunState& state) {
  if (initialized_) throw Error("Session::SetState: give the state before Initialize()");
  if (state.substructures.size() != subs_.size()) {
    throw ConfigError(fmt::format("the run state has {} substructures, the run's config {}",
                                  state.substructures.size(), subs_.size()));
  }
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    const auto& entry = state.substructures[s];
    if (entry.value("slot", "") != spec_.substructures[s].slot) {
      throw ConfigError(fmt::format("the run state's substructure {} is slot '{}', the config's "
                                    "is '{}'", s, entry.value("slot", ""),
                                    spec_.substructures[s].slot));
    }
  }
  resume_ = state;
}

RunState Session::GetState() const {
  RunState state;
  if (scheme_) state.scheme = scheme_->SaveState();
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    state.substructures.push_back(
        {{"slot", spec_.substructures[s].slot}, {"state", subs_[s]->SaveState()}});
  }
  state.statistics = ToJson(stats_);
  state.stiffness = stiffness_record_;
  state.inputs = spec_.source.inputs;
  state.constraint_forces = forces_ ? forces_->size() : 0;
  return state;
}

const schemes::CommittedPoint& Session::committed() const {
  if (!scheme_) throw Error("Session::committed: nothing is committed before Initialize()");
  return scheme_->committed();
}

long Session::EstimatedStepsLeft() const {
  return scheme_ ? scheme_->EstimatedStepsLeft(spec_.scheme.duration) : 0;
}

double Session::WallTime() const {
  return wall_offset_ +
         std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
}

void Session::UpdateStatistics(double t) {
  stats_.sim_time = t;
  stats_.wall_time = WallTime();
  stats_.physical_evaluations = 0;
  for (const auto& s : subs_) {
    stats_.physical_evaluations += s->evaluations();
    for (int k = 0; k < s->num_actuators(); ++k) {
      stats_.lab_time = std::max(stats_.lab_time, s->actuator_exchange(k).lab_time);
    }
  }
  stats_.slowdown = t > 0.0 && physical_count_ > 0 ? stats_.lab_time / t : 0.0;
  stats_.wall_slowdown = t > 0.0 ? stats_.wall_time / t : 0.0;
}

void Session::FillRow(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r,
                      bool measured) {
  Eigen::Index c = 0;
  row_(c++) = t;
  row_.segment(c, x.size()) = x;
  c += x.size();
  row_.segment(c, r.size()) = r;
  c += r.size();
  for (const auto& s : subs_) {
    if (!s->is_physical()) continue;
    for (int k = 0; k < s->num_actuators(); ++k) {
      const auto e = s->actuator_exchange(k);
      for (double v : {e.command, e.position, e.force, e.lab_time}) {
        row_(c++) = measured ? v : std::numeric_limits<double>::quiet_NaN();
      }
    }
  }
  if (forces_) forces_->Fill(t, x, r, row_.data() + c);
}

void Session::Publish(RowKind kind, long step, double t, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& r) {
  FillRow(t, x, r, kind == RowKind::kCommitted);
  ++stats_.rows;
  CommitEvent event;
  event.kind = kind;
  event.step = step;
  event.t = t;
  event.x = {x.data(), static_cast<std::size_t>(x.size())};
  event.r = {r.data(), static_cast<std::size_t>(r.size())};
  event.row = {row_.data(), static_cast<std::size_t>(row_.size())};
  event.statistics = stats_;
  if (kind == RowKind::kCommitted) {
    event.finished = scheme_ && scheme_->finished();
    event.steps_left = EstimatedStepsLeft();
    event.state = [this] { return GetState(); };  // one pointer: no allocation
    if (pacer_ != nullptr) event.real_time = pacer_->Sample();
  }
  for (SessionObserver* o : observers_) o->OnCommit(event);
}

void Session::PublishTrial(const schemes::TrialPoint& at,
                           const Eigen::Ref<const Eigen::VectorXd>& d,
                           const Eigen::Ref<const Eigen::VectorXd>& r) {
  std::size_t k = 0;
  for (const auto& s : subs_) {
    for (int a = 0; a < s->num_actuators(); ++a) exchanges_[k++] = s->actuator_exchange(a);
  }
  const TrialEvent event{at, {d.data(), static_cast<std::size_t>(d.size())},
                         {r.data(), static_cast<std::size_t>(r.size())}, exchanges_};
  for (SessionObserver* o : observers_) o->OnTrial(event);
}

void Session::BuildScheme() {
  scheme_ = schemes::MakeScheme(spec_.scheme.config, spec_.scheme.tableau, spec_.scheme.dt,
                                spec_.scheme.duration, spec_.scheme.steps, model(),
                                SlotInfoOf(subs_, slot_of_, model().num_slots()));
}

StepResult Session::Initialize() {
  if (initialized_) throw Error("Session::Initialize: called twice");
  // A real-time run's stepping thread writes no file (real_time_setup.h).
  if (paced_loop_ != nullptr) queue_ = QueueObservers(*this, *paced_loop_);
  initialized_ = true;
  wall_start_ = std::chrono::steady_clock::now();
  try {
    // Records first: a run that cannot write them must not move anything.
    const StartEvent start{spec_, slot_map_, subs_, has_physical(), resume_state(),
                           paced_loop_ ? paced_loop_->clock_name() : std::string()};
    for (SessionObserver* o : observers_) o->OnStart(start);
    for (auto& s : subs_) s->Activate();
    if (resume_) {
      RestoreFromState();
    } else {
      const int n = model().num_coordinates();
      multibody::Data<double> data(model());
      Eigen::VectorXd d0(model().num_slots());
      multibody::CalcSlotDisplacements<double>(model(), data, 0.0, spec_.x0.head(n), d0);
      // Where every actuator is, against the first command, before anything moves.
      CheckStart(d0);
      MeasureRequestedStiffness();
      BuildScheme();
      // The initial state: tried (stage 0 of step 0), committed, journalled.
      seam_->Trial({0, 0, 0.0}, d0, r0_);
      for (auto& s : subs_) s->Commit();
      scheme_->Start(0.0, spec_.x0, r0_);
      UpdateStatistics(0.0);
      Publish(RowKind::kCommitted, 0, 0.0, spec_.x0, r0_);
    }
    t_now_ = scheme_->committed().t;
  } catch (const std::exception& e) {
    return Fail(e);
  }
  result_ = {SessionStatus::kWorking, ""};
  return result_;
}

StepResult Session::Step() {
  if (!initialized_) throw Error("Session::Step: call Initialize() first");
  if (result_.status != SessionStatus::kWorking) return result_;
  try {
    scheme_->Step(*seam_, *rows_sink_);
    const schemes::CommittedPoint& p = scheme_->committed();
    for (auto& s : subs_) s->Commit();
    stats_.steps = p.step;
    t_now_ = p.t;
    UpdateStatistics(p.t);
    Publish(RowKind::kCommitted, p.step, p.t, p.x, p.r);
    if (scheme_->finished()) return Finish();
    if (stop_requested_.load(std::memory_order_relaxed)) {
      throw Interrupted(fmt::format("{} at t = {} s after {} steps; "
                                    "every committed step is kept{}",
                                    stop_reason_.empty() ? "interrupted by the operator"
                                                         : stop_reason_, p.t, p.step,
                                    spec_.output.files ? " in " + spec_.output.csv_path : ""));
    }
  } catch (const std::exception& e) {
    return Fail(e);
  }
  return result_;
}

void Session::CheckStart(const Eigen::VectorXd& d0) {
  start_record_ = nlohmann::json::array();
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    const auto& slots = slot_of_[s];
    d_slots_.resize(slots.size());
    for (std::size_t k = 0; k < slots.size(); ++k) d_slots_[k] = d0(slots[k]);
    substructures::Substructure::StartRequest request{slot_map_.substructures[s].name, d_slots_,
                                                      spec_.start_ramp, {}};
    nlohmann::json record = subs_[s]->CheckStart(request);
    if (!record.is_null()) start_record_.push_back(std::move(record));
  }
}

void Session::HoldBetweenSteps() noexcept {
  ++holds_;
  for (auto& s : subs_) s->Hold();
}

StepResult Session::InterruptBetweenSteps() {
  if (!initialized_ || result_.status != SessionStatus::kWorking) return result_;
  const schemes::CommittedPoint& p = scheme_->committed();
  try {
    // Thrown so that error() holds it, as for a stop after a step.
    throw Interrupted(fmt::format("interrupted by the operator at t = {} s after {} steps; "
                                  "every committed step is kept{}", p.t, p.step,
                                  spec_.output.files ? " in " + spec_.output.csv_path : ""));
  } catch (const std::exception& e) {
    return Fail(e);
  }
}

StepResult Session::ContinueAfterHold() {
  if (result_.status != SessionStatus::kWorking) return result_;
  try {
    for (auto& s : subs_) s->Activate();
  } catch (const std::exception& e) {
    return Fail(e);
  }
  return result_;
}

void Session::RecordOperatorAction(const nlohmann::json& action) {
  for (SessionObserver* o : observers_) o->OnOperatorAction(action);
}

}  // namespace hybridtest::runner
