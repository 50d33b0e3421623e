// See rt_plant.h.
#include "hybridtest/transfer/rt_plant.h"

#include <fmt/core.h>

#include <cmath>

namespace hybridtest::transfer {

const char* PlantKindName(PlantKind kind) {
  switch (kind) {
    case PlantKind::kIdeal: return "ideal";
    case PlantKind::kElectromechanical: return "electromechanical";
    case PlantKind::kServoHydraulic: return "servo_hydraulic";
  }
  return "?";
}

double SpecimenLaw::Force(double x, double v, double a) const {
  const double damper = damping_exponent == 1.0
                            ? damping * v
                            : damping * std::copysign(std::pow(std::abs(v), damping_exponent), v);
  return mass * a + stiffness * x + damper;
}

void ValidateRtPlantConfig(const RtPlantConfig& c, const std::string& where) {
  auto fail = [&](const std::string& what) {
    throw ConfigError(fmt::format("{}: {}", where, what));
  };
  if (!(c.delay >= 0.0) || !std::isfinite(c.delay)) {
    fail(fmt::format("delay = {}: expected a delay ≥ 0 in s", c.delay));
  }
  if (!(c.rate_hz > 0.0)) fail(fmt::format("rate_hz = {}: expected a rate > 0 in Hz", c.rate_hz));
  const auto& s = c.specimen;
  if (!(s.mass >= 0.0) || !(s.stiffness >= 0.0) || !(s.damping >= 0.0)) {
    fail("specimen: mass [kg], stiffness [N/m] and damping must be ≥ 0");
  }
  if (!(s.damping_exponent > 0.0)) {
    fail(fmt::format("specimen.damping_exponent = {}: expected α > 0", s.damping_exponent));
  }
  if (c.kind == PlantKind::kElectromechanical && !(c.lag > 0.0)) {
    fail(fmt::format("lag = {}: an electromechanical plant needs its time constant > 0 in s",
                     c.lag));
  }
  if (c.kind == PlantKind::kServoHydraulic) {
    if (!(s.mass > 0.0)) {
      fail("a servo_hydraulic plant needs specimen.mass > 0 in kg (the specimen closes the "
           "control–structure interaction loop)");
    }
    const auto& k = c.servo;
    if (!(k.a1_beta0 > 0 && k.a2 >= 0 && k.beta1 > 0 && k.beta2 > 0 && k.a3 > 0 && k.gain > 0)) {
      fail("servo: a1_beta0, beta1, beta2, a3 and gain must be > 0 and a2 ≥ 0");
    }
  }
}

RtPlant::RtPlant(RtPlantConfig config) : config_(std::move(config)) {
  ValidateRtPlantConfig(config_, "rt_plant");
  last_.position = config_.p0;
}

std::string RtPlant::Describe() const {
  const auto& s = config_.specimen;
  return fmt::format("rt_plant ({}, delay {} s{}; specimen m = {} kg, k = {} N/m, c = {}, "
                     "α = {})", PlantKindName(config_.kind), config_.delay,
                     config_.kind == PlantKind::kElectromechanical
                         ? fmt::format(", lag {} s", config_.lag) : std::string(),
                     s.mass, s.stiffness, s.damping, s.damping_exponent);
}

BenchAnnouncement RtPlant::Announce() const {
  BenchAnnouncement a;
  a.actuators = {{config_.p0, std::nullopt}};
  a.source = "rt_plant";
  return a;
}

double RtPlant::SettledDisplacement(double u) const {
  if (config_.kind != PlantKind::kServoHydraulic) return u;
  const auto& k = config_.servo;
  // Static loop: β2 w = a1β0 (g u − x), w = a3 F, F = k x.
  return k.a1_beta0 * k.gain * u /
         (k.a1_beta0 + k.beta2 * k.a3 * config_.specimen.stiffness);
}

std::complex<double> RtPlant::FrequencyResponse(double omega) const {
  using cd = std::complex<double>;
  const cd s(0.0, omega);
  const cd delay = std::exp(-s * config_.delay);
  switch (config_.kind) {
    case PlantKind::kIdeal: return delay;
    case PlantKind::kElectromechanical: return delay / (1.0 + s * config_.lag);
    case PlantKind::kServoHydraulic: {
      const auto& k = config_.servo;
      const auto& sp = config_.specimen;
      const cd gsp = 1.0 / (sp.mass * s * s + sp.damping * s + sp.stiffness);
      const cd ga = 1.0 / (s + k.a3);
      const cd gs = k.a1_beta0 / (s * s + k.beta1 * s + k.beta2);
      const cd h = ga * gsp / (1.0 + k.a2 * s * ga * gsp);
      return delay * k.gain * gs * h / (1.0 + gs * h);
    }
  }
  return delay;
}

std::optional<double> RtPlant::PhaseDelay(double omega, double tick) const {
  const double hold = config_.kind == PlantKind::kIdeal ? 0.0 : 0.5 * tick;
  return -std::arg(FrequencyResponse(omega)) / omega + hold;
}

void RtPlant::StartPaced(double tick, const Clock& clock) {
  if (!(tick > 0.0)) throw ConfigError(fmt::format("rt_plant: tick = {}: expected > 0 s", tick));
  clock_ = &clock;
  tick_ = tick;
  t_ = clock.Now();
  const std::size_t capacity =
      static_cast<std::size_t>(std::ceil(config_.delay / tick)) + 8;
  hist_t_.assign(capacity, 0.0);
  hist_c_.assign(capacity, 0.0);
  hist_head_ = 0;
  hist_size_ = 0;
  // Settled at the last command (the settled trial at step 0 put it there).
  const double u0 = initial_command_ - config_.p0;
  const double x0 = SettledDisplacement(u0);
  y_ = {};
  y_[3] = x0;
  if (config_.kind == PlantKind::kServoHydraulic) {
    y_[2] = config_.specimen.stiffness * x0;  // F
    y_[0] = config_.servo.a3 * y_[2];         // w
  }
  x_prev_ = x0;
  t_prev_ = t_;
}

double RtPlant::DelayedCommand(double s) const {
  const double at = s - config_.delay + 1e-12;
  // Newest first: the command in force at time `at`.
  for (std::size_t i = 0; i < hist_size_; ++i) {
    const std::size_t k = (hist_head_ + hist_t_.size() - 1 - i) % hist_t_.size();
    if (hist_t_[k] <= at) return hist_c_[k];
  }
  return initial_command_;
}

void RtPlant::Rates(const State& y, double u, State& dy) const {
  const auto& sp = config_.specimen;
  if (config_.kind == PlantKind::kElectromechanical) {
    dy = {0.0, 0.0, 0.0, (u - y[3]) / config_.lag, 0.0};
    return;
  }
  const auto& k = config_.servo;
  const double e = k.gain * u - y[3];
  dy[0] = y[1];
  dy[1] = k.a1_beta0 * e - k.beta1 * y[1] - k.beta2 * y[0];
  dy[2] = y[0] - k.a2 * y[4] - k.a3 * y[2];
  dy[3] = y[4];
  dy[4] = (y[2] - sp.Force(y[3], y[4], 0.0)) / sp.mass;
}

void RtPlant::Advance(double t) {
  const double span = t - t_;
  if (!(span > 0.0)) return;
  if (config_.kind != PlantKind::kIdeal) {
    const long n = std::max(1L, static_cast<long>(std::ceil(span * config_.rate_hz - 1e-9)));
    const double h = span / static_cast<double>(n);
    State k1, k2, k3, k4, tmp;
    for (long i = 0; i < n; ++i) {
      const double u = DelayedCommand(t_ + static_cast<double>(i) * h) - config_.p0;
      Rates(y_, u, k1);
      for (int j = 0; j < 5; ++j) tmp[j] = y_[j] + 0.5 * h * k1[j];
      Rates(tmp, u, k2);
      for (int j = 0; j < 5; ++j) tmp[j] = y_[j] + 0.5 * h * k2[j];
      Rates(tmp, u, k3);
      for (int j = 0; j < 5; ++j) tmp[j] = y_[j] + h * k3[j];
      Rates(tmp, u, k4);
      for (int j = 0; j < 5; ++j) y_[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
      if (config_.kind == PlantKind::kElectromechanical) y_[4] = (u - y_[3]) / config_.lag;
    }
  }
  t_ = t;
}

Measurement RtPlant::Measure(double t) const {
  Measurement m;
  m.lab_time = t;
  const auto& sp = config_.specimen;
  switch (config_.kind) {
    case PlantKind::kIdeal: {
      const double x = DelayedCommand(t) - config_.p0;
      const double v = t > t_prev_ ? (x - x_prev_) / (t - t_prev_) : 0.0;
      m.position = config_.p0 + x;
      m.force = sp.Force(x, v, 0.0);
      break;
    }
    case PlantKind::kElectromechanical:
      m.position = config_.p0 + y_[3];
      m.force = sp.Force(y_[3], y_[4], -y_[4] / config_.lag);
      break;
    case PlantKind::kServoHydraulic:
      m.position = config_.p0 + y_[3];
      m.force = y_[2];
      break;
  }
  return m;
}

void RtPlant::Execute(std::span<const double> commands, std::span<Measurement> out) {
  RequireOneActuator(commands, out, "rt_plant");
  out[0] = Step(commands[0]);
}

Measurement RtPlant::Step(double command) {
  if (!active_) {
    throw TransferError(fmt::format("rt_plant: Execute({} m) while not active (after Hold() "
                                    "or before Activate())", command));
  }
  ++commands_;
  if (clock_ == nullptr) {
    // Settled (pseudo-dynamic): the static response, no rate.
    initial_command_ = command;
    const double x = SettledDisplacement(command - config_.p0);
    last_ = {config_.p0 + x, config_.specimen.Force(x, 0.0, 0.0), 0.0, 0};
    return last_;
  }
  const double t = clock_->Now();
  Advance(t);
  // The new command, in force from t on.
  hist_t_[hist_head_] = t;
  hist_c_[hist_head_] = command;
  hist_head_ = (hist_head_ + 1) % hist_t_.size();
  if (hist_size_ < hist_t_.size()) ++hist_size_;
  last_ = Measure(t);
  if (config_.kind == PlantKind::kIdeal) {
    x_prev_ = last_.position - config_.p0;
    t_prev_ = t;
  }
  return last_;
}

}  // namespace hybridtest::transfer
