// See monitor_state.h.
#include "hybridtest/monitor/monitor_state.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace hybridtest::monitor {
namespace {

// A double as JSON: null when it is not finite (JSON has no NaN).
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json LimitsJson(const transfer::SafetyLimits& l) {
  return {{"stroke_min", l.stroke_min}, {"stroke_max", l.stroke_max},
          {"max_increment", l.max_increment}, {"force_soft", l.force_soft},
          {"force_hard", l.force_hard}};
}

// Answers kept for different `since` of /api/series (viewers that poll at the same pace ask
// for the same one); the oldest goes first.
constexpr std::size_t kCachedBodies = 16;

}  // namespace

std::string JsonText(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

Margin CalcMargin(const transfer::SafetyLimits& limits, double position, double force) {
  Margin m;
  const double half = 0.5 * (limits.stroke_max - limits.stroke_min);
  const double mid = 0.5 * (limits.stroke_max + limits.stroke_min);
  m.force_fraction = limits.force_hard > 0.0 ? std::abs(force) / limits.force_hard : 0.0;
  m.stroke_fraction = half > 0.0 ? std::abs(position - mid) / half : 0.0;
  const bool tripped = std::abs(force) >= limits.force_hard || position <= limits.stroke_min ||
                       position >= limits.stroke_max;
  const bool near = std::abs(force) >= std::min(limits.force_soft, kNearFraction * limits.force_hard) ||
                    m.stroke_fraction >= kNearFraction;
  m.level = tripped ? "tripped" : near ? "near" : "normal";
  return m;
}

MonitorState::MonitorState(std::size_t history_capacity)
    : capacity_(std::max<std::size_t>(history_capacity, 2)) {}

FrameLayout MonitorState::SetIdentity(RunIdentity identity, FrameLayout layout,
                                      std::vector<ActuatorInfo> actuators) {
  std::lock_guard lock(mutex_);
  ++version_;
  realtime_.Configure(identity.real_time);
  layout.real_time = realtime_.columns();
  identity_ = std::move(identity);
  layout_ = layout;
  actuators_ = std::move(actuators);
  latest_.assign(layout_.width(), std::nan(""));
  return layout_;
}

void MonitorState::SetStatus(const std::string& status, const std::string& reason,
                             const std::string& resume_command) {
  std::lock_guard lock(mutex_);
  ++version_;
  if (status_ == "holding" && status == "running") window_wall_ = -1.0;  // a hold is no rate
  status_ = status;
  reason_ = reason;
  resume_command_ = resume_command;
}

std::string MonitorState::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void MonitorState::AddFrame(std::span<const double> frame) {
  std::lock_guard lock(mutex_);
  ++version_;
  if (frame.size() != layout_.width()) return;
  latest_.assign(frame.begin(), frame.end());
  if (status_ == "starting") status_ = "running";
  realtime_.Add(frame.subspan(layout_.rt(0), layout_.real_time));
  // The rate of simulated time, for the ETA.
  const double t = frame[1], wall = frame[2];
  if (window_wall_ < 0.0) {
    window_t_ = t;
    window_wall_ = wall;
  } else if (wall - window_wall_ >= 0.5) {
    const double rate = (t - window_t_) / (wall - window_wall_);
    rate_ = rate_ > 0.0 ? 0.7 * rate_ + 0.3 * rate : rate;
    window_t_ = t;
    window_wall_ = wall;
  }
  // The history, thinned to stay bounded.
  if (frames_ % stride_ == 0) {
    history_.emplace_back(frame.begin(), frame.end());
    history_.back().push_back(static_cast<double>(frames_));
    if (history_.size() >= capacity_) Thin();
  }
  ++frames_;
}

void MonitorState::Thin() {
  std::size_t k = 0;
  for (std::size_t i = 0; i < history_.size(); i += 2, ++k) {
    if (k != i) history_[k] = std::move(history_[i]);  // never a self-move (it empties)
  }
  history_.resize(k);
  stride_ *= 2;
  ++generation_;
}

void MonitorState::AddResume(double t) {
  std::lock_guard lock(mutex_);
  ++version_;
  resumes_.push_back(t);
}

void MonitorState::AddAction(nlohmann::json action) {
  std::lock_guard lock(mutex_);
  ++version_;
  actions_.push_back(std::move(action));
  if (actions_.size() > 100) actions_.erase(actions_.begin());  // the page shows the latest
}

void MonitorState::SetDropped(long frames) {
  std::lock_guard lock(mutex_);
  ++version_;
  dropped_ = frames;
}

void MonitorState::SetActionsPolicy(const std::string& policy) {
  std::lock_guard lock(mutex_);
  ++version_;
  actions_policy_ = policy;
}

void MonitorState::SetRealTime(nlohmann::json realtime) {
  std::lock_guard lock(mutex_);
  ++version_;
  realtime_.SetRecorded(std::move(realtime));
}

void MonitorState::SetRecorded(const RecordedTotals& totals) {
  std::lock_guard lock(mutex_);
  ++version_;
  recorded_ = totals;
}

long MonitorState::frames() const {
  std::lock_guard lock(mutex_);
  return frames_;
}

nlohmann::json MonitorState::StateJson() const {
  std::lock_guard lock(mutex_);
  const bool any = frames_ > 0;
  auto at = [&](std::size_t i) { return any ? Number(latest_[i]) : nlohmann::json(); };
  const double t = any ? latest_[1] : 0.0;
  const double end = identity_.end_time;
  nlohmann::json eta;
  if (status_ == "finished") {
    eta = 0.0;
  } else if (rate_ > 0.0 && end > 0.0) {
    eta = std::max(0.0, (end - t) / rate_);
  }
  nlohmann::json slots = nlohmann::json::array();
  for (int s = 0; s < layout_.slots; ++s) {
    slots.push_back({{"name", s < int(identity_.slots.size()) ? identity_.slots[s] : ""},
                     {"d", at(layout_.d(s))}, {"r", at(layout_.r(s))}});
  }
  nlohmann::json actuators = nlohmann::json::array();
  for (int a = 0; a < layout_.actuators && a < int(actuators_.size()); ++a) {
    const ActuatorInfo& info = actuators_[a];
    const double position = any ? latest_[layout_.position(a)] : std::nan("");
    const double force = any ? latest_[layout_.force(a)] : std::nan("");
    nlohmann::json j = {{"name", info.name}, {"substructure", info.substructure},
                        {"index", info.index}, {"slots", info.slots},
                        {"p0", info.p0 ? nlohmann::json(*info.p0) : nlohmann::json()},
                        {"command", at(layout_.command(a))}, {"position", Number(position)},
                        {"displacement", info.p0 ? Number(position - *info.p0) : nlohmann::json()},
                        {"force", Number(force)}, {"limits", nullptr}, {"margin", nullptr}};
    if (info.limits) {
      j["limits"] = LimitsJson(*info.limits);
      if (std::isfinite(force) && std::isfinite(position)) {
        const Margin m = CalcMargin(*info.limits, position, force);
        j["margin"] = {{"force_fraction", m.force_fraction},
                       {"stroke_fraction", m.stroke_fraction}, {"level", m.level}};
      }
    }
    actuators.push_back(std::move(j));
  }
  return {{"status", status_},
          {"reason", reason_},
          {"resume_command", resume_command_},
          {"t", t},
          {"end_time", end},
          {"fraction", end > 0.0 ? std::min(1.0, t / end) : 0.0},
          {"step", any ? static_cast<long>(latest_[0]) : 0},
          {"physical_evaluations",
           recorded_.physical_evaluations.value_or(any ? static_cast<long>(latest_[4]) : 0)},
          {"wall_time", recorded_.wall_time.value_or(any ? latest_[2] : 0.0)},
          {"lab_time", recorded_.lab_time.value_or(any ? latest_[3] : 0.0)},
          {"eta_s", eta},
          {"sim_rate", rate_},
          {"identity", {{"config", identity_.config}, {"model", identity_.model},
                        {"specimen", identity_.specimen}, {"bench", identity_.bench},
                        {"command", identity_.command}, {"csv", identity_.csv},
                        {"mode", identity_.mode}, {"real_time", identity_.real_time.enabled}}},
          {"slots", slots},
          {"actuators", actuators},
          {"resumes", resumes_},
          {"actions", actions_},
          {"actions_policy", actions_policy_},
          {"frames", frames_},
          {"dropped_frames", dropped_},
          {"history_generation", generation_},
          {"realtime", realtime_.Json()}};
}

nlohmann::json MonitorState::SeriesJson(long since, long generation) const {
  std::lock_guard lock(mutex_);
  const bool all = generation != generation_;
  // Columns: t, then per slot d and r, then per actuator command, position, force.
  nlohmann::json columns = {{"t", nlohmann::json::array()}, {"seq", nlohmann::json::array()}};
  auto column = [&](const std::string& name, std::size_t i) {
    nlohmann::json values = nlohmann::json::array();
    for (const auto& f : history_) {
      if (all || f.back() > static_cast<double>(since)) values.push_back(Number(f[i]));
    }
    columns[name] = std::move(values);
  };
  column("t", 1);
  column("seq", layout_.width());
  // (Names by fmt: GCC 12 warns -Wrestrict inside `"d" + std::to_string(s)`.)
  for (int s = 0; s < layout_.slots; ++s) {
    column(fmt::format("d{}", s), layout_.d(s));
    column(fmt::format("r{}", s), layout_.r(s));
  }
  for (int a = 0; a < layout_.actuators; ++a) {
    column(fmt::format("command{}", a), layout_.command(a));
    column(fmt::format("position{}", a), layout_.position(a));
    column(fmt::format("force{}", a), layout_.force(a));
  }
  return {{"generation", generation_}, {"reset", all}, {"slots", layout_.slots},
          {"actuators", layout_.actuators}, {"columns", columns}};
}

std::shared_ptr<const std::string> MonitorState::Cached(const std::vector<CachedBody>& cache,
                                                        long since, bool all, long version,
                                                        BodyClock::time_point now) {
  const auto interval = std::chrono::duration<double>(kBodyInterval);
  for (const CachedBody& c : cache) {
    if (c.since != since || c.all != all) continue;
    if (c.version == version || now - c.built < interval) return c.text;
  }
  return nullptr;
}

void MonitorState::Store(std::vector<CachedBody>& cache, CachedBody body) {
  std::erase_if(cache, [&](const CachedBody& c) { return c.since == body.since && c.all == body.all; });
  if (cache.size() >= kCachedBodies) {
    cache.erase(std::min_element(cache.begin(), cache.end(), [](const auto& a, const auto& b) {
      return a.built < b.built;
    }));
  }
  cache.push_back(std::move(body));
}

std::shared_ptr<const std::string> MonitorState::StateBody() const {
  const std::lock_guard build(body_mutex_);
  const auto now = BodyClock::now();
  long version = 0;
  {
    const std::lock_guard lock(mutex_);
    version = version_;
  }
  if (auto text = Cached(state_bodies_, 0, false, version, now)) return text;
  auto text = std::make_shared<const std::string>(JsonText(StateJson()));
  ++body_builds_;
  Store(state_bodies_, {version, 0, false, now, text});
  return text;
}

std::shared_ptr<const std::string> MonitorState::SeriesBody(long since, long generation) const {
  const std::lock_guard build(body_mutex_);
  const auto now = BodyClock::now();
  long version = 0;
  bool all = false;
  {
    const std::lock_guard lock(mutex_);
    version = version_;
    all = generation != generation_;
  }
  if (all) since = -1;  // the whole history, whatever the viewer had
  if (auto text = Cached(series_bodies_, since, all, version, now)) return text;
  auto text = std::make_shared<const std::string>(
      JsonText(SeriesJson(since, all ? -1 : generation)));
  ++body_builds_;
  Store(series_bodies_, {version, since, all, now, text});
  return text;
}

long MonitorState::body_builds() const {
  const std::lock_guard build(body_mutex_);
  return body_builds_;
}

}  // namespace hybridtest::monitor
