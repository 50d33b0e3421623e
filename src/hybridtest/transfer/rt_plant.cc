// See rt_plant.h.
#include "hybridtest/transfer/rt_plant.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <algorithm>
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

SpecimenLaw SpecimenLaw::One(double mass, double stiffness, double damping,
                             double damping_exponent) {
  return {{mass}, {stiffness}, {damping}, damping_exponent};
}

double SpecimenLaw::Force(int i, const double* x, const double* v, double a_i) const {
  const auto n = mass.size();
  const auto row = static_cast<std::size_t>(i) * n;
  double f = mass[static_cast<std::size_t>(i)] * a_i;
  for (std::size_t j = 0; j < n; ++j) f += stiffness[row + j] * x[j];
  for (std::size_t j = 0; j < n; ++j) {
    const double c = damping[row + j];
    if (c == 0.0) continue;
    f += damping_exponent == 1.0
             ? c * v[j]
             : c * std::copysign(std::pow(std::abs(v[j]), damping_exponent), v[j]);
  }
  return f;
}

void ValidateRtPlantConfig(const RtPlantConfig& c, const std::string& where) {
  auto fail = [&](const std::string& what) {
    throw ConfigError(fmt::format("{}: {}", where, what));
  };
  const int n = c.size();
  if (n < 1) fail("expected at least one actuator");
  if (!(c.rate_hz > 0.0)) fail(fmt::format("rate_hz = {}: expected a rate > 0 in Hz", c.rate_hz));
  const auto& s = c.specimen;
  const auto nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  if (s.mass.size() != static_cast<std::size_t>(n) || s.stiffness.size() != nn ||
      s.damping.size() != nn) {
    fail(fmt::format("specimen: expected {} masses and {} × {} stiffness and damping matrices "
                     "(one row and column per actuator)", n, n, n));
  }
  auto all = [](const std::vector<double>& v, auto ok) { return std::all_of(v.begin(), v.end(), ok); };
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!all(s.mass, [](double v) { return v >= 0.0; }) || !all(s.stiffness, finite) ||
      !all(s.damping, finite)) {
    fail("specimen: mass [kg] must be ≥ 0, stiffness [N/m] and damping finite");
  }
  for (int i = 0; i < n; ++i) {
    const auto d = static_cast<std::size_t>(i) * (static_cast<std::size_t>(n) + 1);
    if (!(s.stiffness[d] >= 0.0) || !(s.damping[d] >= 0.0)) {
      fail("specimen: stiffness [N/m] and damping must be ≥ 0 on the diagonal");
    }
  }
  if (!(s.damping_exponent > 0.0)) {
    fail(fmt::format("specimen.damping_exponent = {}: expected α > 0", s.damping_exponent));
  }
  for (int i = 0; i < n; ++i) {
    const ActuatorPlant& a = c.actuators[static_cast<std::size_t>(i)];
    const std::string who = n > 1 ? fmt::format("actuator {}: ", i + 1) : std::string();
    if (!(a.delay >= 0.0) || !std::isfinite(a.delay)) {
      fail(fmt::format("{}delay = {}: expected a delay ≥ 0 in s", who, a.delay));
    }
    if (c.kind == PlantKind::kElectromechanical && !(a.lag > 0.0)) {
      fail(fmt::format("{}lag = {}: an electromechanical plant needs its time constant > 0 in s",
                       who, a.lag));
    }
    if (c.kind != PlantKind::kServoHydraulic) continue;
    if (!(s.mass[static_cast<std::size_t>(i)] > 0.0)) {
      fail(fmt::format("{}a servo_hydraulic plant needs specimen.mass > 0 in kg (the specimen "
                       "closes the control–structure interaction loop)", who));
    }
    const auto& k = a.servo;
    if (!(k.a1_beta0 > 0 && k.a2 >= 0 && k.beta1 > 0 && k.beta2 > 0 && k.a3 > 0 && k.gain > 0)) {
      fail(fmt::format("{}servo: a1_beta0, beta1, beta2, a3 and gain must be > 0 and a2 ≥ 0",
                       who));
    }
  }
}

RtPlant::RtPlant(RtPlantConfig config) : config_(std::move(config)) {
  ValidateRtPlantConfig(config_, "rt_plant");
  n_ = config_.size();
  const auto n = static_cast<std::size_t>(n_);
  for (auto* v : {&y_, &k1_, &k2_, &k3_, &k4_, &tmp_}) v->assign(5 * n, 0.0);
  u_.assign(n, 0.0);
  x_prev_.assign(n, 0.0);
  xs_.assign(n, 0.0);
  vs_.assign(n, 0.0);
  initial_command_.assign(n, 0.0);
  last_.assign(n, Measurement{});
  for (std::size_t i = 0; i < n; ++i) last_[i].position = config_.actuators[i].p0;
}

std::string RtPlant::Describe() const {
  const auto& s = config_.specimen;
  const auto& a = config_.actuators;
  if (n_ == 1) {
    return fmt::format("rt_plant ({}, delay {} s{}; specimen m = {} kg, k = {} N/m, c = {}, "
                       "α = {})", PlantKindName(config_.kind), a[0].delay,
                       config_.kind == PlantKind::kElectromechanical
                           ? fmt::format(", lag {} s", a[0].lag) : std::string(),
                       s.mass[0], s.stiffness[0], s.damping[0], s.damping_exponent);
  }
  std::vector<double> delays;
  for (const ActuatorPlant& p : a) delays.push_back(p.delay);
  return fmt::format("rt_plant of {} actuators ({}, delays [{}] s; specimen m = [{}] kg, "
                     "K = [{}] N/m)", n_, PlantKindName(config_.kind), fmt::join(delays, ", "),
                     fmt::join(s.mass, ", "), fmt::join(s.stiffness, ", "));
}

BenchAnnouncement RtPlant::Announce() const {
  BenchAnnouncement a;
  for (const ActuatorPlant& p : config_.actuators) a.actuators.push_back({p.p0, std::nullopt});
  a.source = "rt_plant";
  return a;
}

std::vector<double> RtPlant::SettledDisplacement(const std::vector<double>& u) const {
  if (config_.kind != PlantKind::kServoHydraulic) return u;
  if (n_ == 1) {
    const auto& k = config_.actuators[0].servo;
    // Static loop: β2 w = a1β0 (g u − x), w = a3 F, F = k x.
    return {k.a1_beta0 * k.gain * u[0] /
            (k.a1_beta0 + k.beta2 * k.a3 * config_.specimen.stiffness[0])};
  }
  // (diag(a1β0) + diag(β2 a3) K) x = diag(a1β0 g) u.
  Eigen::MatrixXd A(n_, n_);
  Eigen::VectorXd b(n_);
  for (int i = 0; i < n_; ++i) {
    const auto& k = config_.actuators[static_cast<std::size_t>(i)].servo;
    for (int j = 0; j < n_; ++j) {
      A(i, j) = k.beta2 * k.a3 * config_.specimen.stiffness[static_cast<std::size_t>(i * n_ + j)];
    }
    A(i, i) += k.a1_beta0;
    b(i) = k.a1_beta0 * k.gain * u[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd x = A.partialPivLu().solve(b);
  return std::vector<double>(x.data(), x.data() + x.size());
}

std::complex<double> RtPlant::FrequencyResponse(double omega, int i, int j) const {
  using cd = std::complex<double>;
  const cd s(0.0, omega);
  const ActuatorPlant& pj = config_.actuators[static_cast<std::size_t>(j)];
  const cd delay = std::exp(-s * pj.delay);
  switch (config_.kind) {
    case PlantKind::kIdeal: return i == j ? delay : cd(0.0);
    case PlantKind::kElectromechanical: return i == j ? delay / (1.0 + s * pj.lag) : cd(0.0);
    case PlantKind::kServoHydraulic: {
      const auto& sp = config_.specimen;
      if (n_ == 1) {
        const auto& k = pj.servo;
        const cd gsp = 1.0 / (sp.mass[0] * s * s + sp.damping[0] * s + sp.stiffness[0]);
        const cd ga = 1.0 / (s + k.a3);
        const cd gs = k.a1_beta0 / (s * s + k.beta1 * s + k.beta2);
        const cd h = ga * gsp / (1.0 + k.a2 * s * ga * gsp);
        return delay * k.gain * gs * h / (1.0 + gs * h);
      }
      // G = (Zs + Ga (Gs + a2 s))⁻¹ Ga Gs g, column j.
      Eigen::MatrixXcd Z(n_, n_);
      Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n_);
      for (int r = 0; r < n_; ++r) {
        const auto& k = config_.actuators[static_cast<std::size_t>(r)].servo;
        for (int c = 0; c < n_; ++c) {
          const auto rc = static_cast<std::size_t>(r * n_ + c);
          Z(r, c) = sp.damping[rc] * s + sp.stiffness[rc];
        }
        const cd ga = 1.0 / (s + k.a3);
        const cd gs = k.a1_beta0 / (s * s + k.beta1 * s + k.beta2);
        Z(r, r) += sp.mass[static_cast<std::size_t>(r)] * s * s + ga * (gs + k.a2 * s);
        if (r == j) rhs(r) = ga * gs * k.gain;
      }
      return delay * Z.partialPivLu().solve(rhs)(i);
    }
  }
  return delay;
}

std::optional<double> RtPlant::PhaseDelay(double omega, double tick) const {
  const double hold = config_.kind == PlantKind::kIdeal ? 0.0 : 0.5 * tick;
  double worst = -std::arg(FrequencyResponse(omega, 0, 0)) / omega + hold;
  for (int i = 1; i < n_; ++i) {
    worst = std::max(worst, -std::arg(FrequencyResponse(omega, i, i)) / omega + hold);
  }
  return worst;
}

void RtPlant::StartPaced(double tick, const Clock& clock) {
  if (!(tick > 0.0)) throw ConfigError(fmt::format("rt_plant: tick = {}: expected > 0 s", tick));
  clock_ = &clock;
  tick_ = tick;
  t_ = clock.Now();
  double longest = 0.0;
  for (const ActuatorPlant& a : config_.actuators) longest = std::max(longest, a.delay);
  const std::size_t capacity = static_cast<std::size_t>(std::ceil(longest / tick)) + 8;
  const auto n = static_cast<std::size_t>(n_);
  hist_t_.assign(capacity, 0.0);
  hist_c_.assign(capacity * n, 0.0);
  hist_head_ = 0;
  hist_size_ = 0;
  // Settled at the last commands (the settled trial at step 0 put them there).
  std::vector<double> u0(n);
  for (std::size_t i = 0; i < n; ++i) u0[i] = initial_command_[i] - config_.actuators[i].p0;
  const std::vector<double> x0 = SettledDisplacement(u0);
  std::fill(y_.begin(), y_.end(), 0.0);
  for (std::size_t i = 0; i < n; ++i) y_[5 * i + 3] = x0[i];
  if (config_.kind == PlantKind::kServoHydraulic) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto row = i * n;
      double f = 0.0;  // F = K x0 (for one actuator exactly k x0)
      for (std::size_t j = 0; j < n; ++j) f += config_.specimen.stiffness[row + j] * x0[j];
      y_[5 * i + 2] = f;                                          // F
      y_[5 * i] = config_.actuators[i].servo.a3 * y_[5 * i + 2];  // w
    }
  }
  x_prev_ = x0;
  t_prev_ = t_;
}

double RtPlant::DelayedCommand(int i, double s) const {
  const auto a = static_cast<std::size_t>(i);
  const double at = s - config_.actuators[a].delay + 1e-12;
  const auto n = static_cast<std::size_t>(n_);
  // Newest first: the command in force at time `at`.
  for (std::size_t h = 0; h < hist_size_; ++h) {
    const std::size_t k = (hist_head_ + hist_t_.size() - 1 - h) % hist_t_.size();
    if (hist_t_[k] <= at) return hist_c_[k * n + a];
  }
  return initial_command_[a];
}

void RtPlant::Rates(const double* y, const double* u, double* dy) const {
  const auto n = static_cast<std::size_t>(n_);
  if (config_.kind == PlantKind::kElectromechanical) {
    for (std::size_t i = 0; i < n; ++i) {
      double* d = dy + 5 * i;
      d[0] = d[1] = d[2] = d[4] = 0.0;
      d[3] = (u[i] - y[5 * i + 3]) / config_.actuators[i].lag;
    }
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    xs_[i] = y[5 * i + 3];
    vs_[i] = y[5 * i + 4];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& k = config_.actuators[i].servo;
    const double* yi = y + 5 * i;
    double* d = dy + 5 * i;
    const double e = k.gain * u[i] - yi[3];
    d[0] = yi[1];
    d[1] = k.a1_beta0 * e - k.beta1 * yi[1] - k.beta2 * yi[0];
    d[2] = yi[0] - k.a2 * yi[4] - k.a3 * yi[2];
    d[3] = yi[4];
    d[4] = (yi[2] - config_.specimen.Force(static_cast<int>(i), xs_.data(), vs_.data(), 0.0)) /
           config_.specimen.mass[i];
  }
}

void RtPlant::Advance(double t) {
  const double span = t - t_;
  if (!(span > 0.0)) return;
  if (config_.kind != PlantKind::kIdeal) {
    const long steps = std::max(1L, static_cast<long>(std::ceil(span * config_.rate_hz - 1e-9)));
    const double h = span / static_cast<double>(steps);
    const std::size_t m = y_.size();
    for (long s = 0; s < steps; ++s) {
      for (int i = 0; i < n_; ++i) {
        u_[static_cast<std::size_t>(i)] =
            DelayedCommand(i, t_ + static_cast<double>(s) * h) -
            config_.actuators[static_cast<std::size_t>(i)].p0;
      }
      Rates(y_.data(), u_.data(), k1_.data());
      for (std::size_t j = 0; j < m; ++j) tmp_[j] = y_[j] + 0.5 * h * k1_[j];
      Rates(tmp_.data(), u_.data(), k2_.data());
      for (std::size_t j = 0; j < m; ++j) tmp_[j] = y_[j] + 0.5 * h * k2_[j];
      Rates(tmp_.data(), u_.data(), k3_.data());
      for (std::size_t j = 0; j < m; ++j) tmp_[j] = y_[j] + h * k3_[j];
      Rates(tmp_.data(), u_.data(), k4_.data());
      for (std::size_t j = 0; j < m; ++j) {
        y_[j] += h / 6.0 * (k1_[j] + 2 * k2_[j] + 2 * k3_[j] + k4_[j]);
      }
      if (config_.kind == PlantKind::kElectromechanical) {
        for (std::size_t i = 0; i < u_.size(); ++i) {
          y_[5 * i + 4] = (u_[i] - y_[5 * i + 3]) / config_.actuators[i].lag;
        }
      }
    }
  }
  t_ = t;
}

void RtPlant::Measure(double t) {
  const auto n = static_cast<std::size_t>(n_);
  const auto& sp = config_.specimen;
  if (config_.kind == PlantKind::kIdeal) {
    for (std::size_t i = 0; i < n; ++i) {
      xs_[i] = DelayedCommand(static_cast<int>(i), t) - config_.actuators[i].p0;
      vs_[i] = t > t_prev_ ? (xs_[i] - x_prev_[i]) / (t - t_prev_) : 0.0;
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      xs_[i] = y_[5 * i + 3];
      vs_[i] = y_[5 * i + 4];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    Measurement& m = last_[i];
    m = Measurement{};
    m.lab_time = t;
    m.position = config_.actuators[i].p0 + xs_[i];
    switch (config_.kind) {
      case PlantKind::kIdeal: m.force = sp.Force(static_cast<int>(i), xs_.data(), vs_.data(), 0.0);
        break;
      case PlantKind::kElectromechanical:
        m.force = sp.Force(static_cast<int>(i), xs_.data(), vs_.data(),
                           -vs_[i] / config_.actuators[i].lag);
        break;
      case PlantKind::kServoHydraulic: m.force = y_[5 * i + 2]; break;
    }
  }
}

void RtPlant::Execute(std::span<const double> commands, std::span<Measurement> out) {
  if (commands.size() != static_cast<std::size_t>(n_) || out.size() != commands.size()) {
    throw TransferError(fmt::format("rt_plant: {} commands and {} measurements for {} "
                                    "actuator(s): give one per actuator", commands.size(),
                                    out.size(), n_));
  }
  Step(commands);
  std::copy(last_.begin(), last_.end(), out.begin());
}

void RtPlant::Step(std::span<const double> commands) {
  if (!active_) {
    throw TransferError(fmt::format("rt_plant: Execute([{}] m) while not active (after Hold() "
                                    "or before Activate())", fmt::join(commands, ", ")));
  }
  ++commands_;
  const auto n = static_cast<std::size_t>(n_);
  if (clock_ == nullptr) {
    // Settled (pseudo-dynamic): the static response, no rate.
    for (std::size_t i = 0; i < n; ++i) {
      initial_command_[i] = commands[i];
      u_[i] = commands[i] - config_.actuators[i].p0;
    }
    const std::vector<double> x = SettledDisplacement(u_);
    std::fill(vs_.begin(), vs_.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      last_[i] = {config_.actuators[i].p0 + x[i],
                  config_.specimen.Force(static_cast<int>(i), x.data(), vs_.data(), 0.0), 0.0, 0};
    }
    return;
  }
  const double t = clock_->Now();
  Advance(t);
  // The new commands, in force from t on.
  hist_t_[hist_head_] = t;
  std::copy(commands.begin(), commands.end(), hist_c_.begin() + static_cast<long>(hist_head_ * n));
  hist_head_ = (hist_head_ + 1) % hist_t_.size();
  if (hist_size_ < hist_t_.size()) ++hist_size_;
  Measure(t);
  if (config_.kind == PlantKind::kIdeal) {
    for (std::size_t i = 0; i < n; ++i) x_prev_[i] = last_[i].position - config_.actuators[i].p0;
    t_prev_ = t;
  }
}

}  // namespace hybridtest::transfer
