// Steady states (multibody/steady_state.h, `hybridtest modes --steady`) against independent
// oracles: the governor's angle arccos(g / (l Ω²)), the sprung pendulum's equilibrium by
// bisection of its scalar equation, and the four-bar's static equilibrium by minimising its
// potential energy with the loop closed by circle intersection (no engine code in either);
// and the refusals (no steady state, nothing restores the coordinate, a dependent one).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <tuple>
#include <nlohmann/json.hpp>

#include "hybridtest/common/error.h"
#include "hybridtest/io/modes_analysis.h"
#include "support/run_command.h"

namespace hybridtest {
namespace {

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kGovernor = kSource + "/tests/modelfile/data/governor.yaml";
const std::string kPendulum = kSource + "/tests/modelfile/data/sprung_pendulum.yaml";
const std::string kFourBar = kSource + "/examples/models/four_bar.yaml";

io::ModesReport Steady(const std::string& path, std::vector<std::pair<std::string, double>> set,
                       const std::string& free) {
  io::ModesRequest request;
  request.path = path;
  request.set = std::move(set);
  request.steady = {free};
  return io::AnalyseModes(request);
}

// A root of f in [a, b] (f(a) f(b) ≤ 0) by bisection to the last bit.
double Bisect(const std::function<double(double)>& f, double a, double b) {
  const double fa0 = f(a);
  for (int i = 0; i < 200 && b - a > 0.0; ++i) {
    const double c = 0.5 * (a + b);
    if (c == a || c == b) break;
    if ((f(c) < 0.0) == (fa0 < 0.0)) a = c; else b = c;
  }
  return 0.5 * (a + b);
}

TEST(SteadyStateTest, GovernorAngleIsArccosOfGOverLOmegaSquared) {
  const double g = 9.81, l = 0.2;
  for (double omega : {7.5, 10.0, 20.0, 40.0}) {
    const io::ModesReport r = Steady(kGovernor, {{"Omega", omega}}, "theta");
    ASSERT_TRUE(r.steady && r.steady->converged);
    const double theta = r.steady->x(1);
    EXPECT_NEAR(theta, std::acos(g / (l * omega * omega)), 1e-10) << "Ω = " << omega;
    EXPECT_LE(r.steady->residual, 1e-10);
    EXPECT_GT(r.steady->iterations, 0);
    EXPECT_EQ(r.analysis.x(2), omega);  // the held spin
    EXPECT_EQ(r.analysis.x(1), theta);  // linearised where it was found
  }
}

TEST(SteadyStateTest, GovernorBelowCriticalSpinFindsOnlyTheHangingState) {
  // Ω < sqrt(g/l) ≈ 7.0 rad/s: θ = 0 is the only steady state.
  const io::ModesReport r = Steady(kGovernor, {{"Omega", 5.0}}, "theta");
  ASSERT_TRUE(r.steady->converged);
  EXPECT_NEAR(r.steady->x(1), 0.0, 1e-10);
}

TEST(SteadyStateTest, AStartThatIsSteadyTakesNoIteration) {
  io::ModesRequest request;
  request.path = kGovernor;
  request.q = std::vector<double>{0.3, std::acos(9.81 / (0.2 * 100.0))};
  request.steady = {"theta"};
  const io::ModesReport r = io::AnalyseModes(request);
  EXPECT_LE(r.steady->iterations, 1);
  EXPECT_EQ(r.steady->x(0), 0.3);  // the held coordinate is not moved
}

TEST(SteadyStateTest, SprungPendulumMatchesBisection) {
  const double m = 1.0, l = 0.5, g = 9.81, th0 = 1.0;
  for (auto [k, T] : {std::pair{8.0, 0.0}, std::pair{8.0, 3.0}, std::pair{2.0, -1.0}}) {
    const io::ModesReport r = Steady(kPendulum, {{"k", k}, {"T", T}}, "q");
    const double want = Bisect(
        [&](double q) { return T - k * (q - th0) - m * g * l * std::sin(q); }, -1.5, 1.5);
    EXPECT_NEAR(r.steady->x(0), want, 1e-12) << "k = " << k << ", T = " << T;
  }
}

// The four-bar's potential V(q1) = ½ k (q1 − th0)² + g Σ m_i y_i, the loop closed by the
// intersection of the circles about A (radius l2) and D (radius l3), elbow up.
TEST(SteadyStateTest, FourBarEquilibriumMinimisesItsPotentialEnergy) {
  const double l1 = 0.1, l2 = 0.3, l3 = 0.25, l0 = 0.3, m1 = 0.5, m2 = 1.2, m3 = 1.0, k = 40,
               th0 = 60.0 * M_PI / 180.0, g = 9.81;
  auto potential = [&](double q1) {
    const double ax = l1 * std::cos(q1), ay = l1 * std::sin(q1);
    const double dx = l0 - ax, dy = -ay, d = std::hypot(dx, dy);
    const double a = (l2 * l2 - l3 * l3 + d * d) / (2 * d);
    const double q2 = std::atan2(dy, dx) + std::acos(a / l2);
    const double by = ay + l2 * std::sin(q2);
    return 0.5 * k * (q1 - th0) * (q1 - th0) +
           g * (m1 * ay / 2 + m2 * (ay + l2 / 2 * std::sin(q2)) + m3 * by / 2);
  };
  auto slope = [&](double q) { return (potential(q + 1e-6) - potential(q - 1e-6)) / 2e-6; };
  const double want = Bisect(slope, 0.8, 1.3);
  io::ModesRequest request;
  request.path = kFourBar;
  request.u = std::vector<double>{0.0, 0.0, 0.0};
  request.steady = {"q1"};
  const io::ModesReport r = io::AnalyseModes(request);
  ASSERT_TRUE(r.steady->converged);
  EXPECT_NEAR(r.steady->x(0), want, 1e-9);
  // Every speed rate vanishes there, the dependent ones too, and the loop is closed.
  EXPECT_LE(r.steady->residual, 1e-10);
  const auto res = multibody::CalcConstraintResiduals(r.built.model, 0.0, r.steady->x);
  EXPECT_LE(res.position, 1e-10);
  // A stable equilibrium: the one oscillatory pair is undamped.
  ASSERT_EQ(r.analysis.modes.size(), 2u);
  EXPECT_NEAR(r.analysis.modes[0].eigenvalue.real(), 0.0, 1e-9);
  EXPECT_GT(std::abs(r.analysis.modes[0].eigenvalue.imag()), 1.0);
}

// The rotor (examples/models/rotor.yaml) driven at Ω: each blade tip, at angle θ_i = q4 +
// 2π(i−1)/3, balances m(−Ω² q_i) = −k q_i + ramp (f_w − m g sin θ_i) along b̂_iy (u̇ = 0),
// so q_i = ramp (f_w − m g sin θ_i) / (k − m Ω²), ramp = 1 − exp(−t/t0). Without the drive
// the generator's damping slows the hub: no steady state.
TEST(SteadyStateTest, DrivenRotorBladesMatchTheTipBalance) {
  const double m = 1.96, k = 7.2e3, f_w = 100.0, g = 9.82, t0 = 0.5;
  for (auto [omega, t, q4] : {std::tuple{20.0, 3.0, 0.3}, std::tuple{40.0, 0.7, -1.1}}) {
    io::ModesRequest request;
    request.path = kSource + "/examples/models/rotor.yaml";
    request.time = t;
    request.q = std::vector<double>{0.0, 0.0, 0.0, q4};
    request.u = std::vector<double>{0.0, 0.0, 0.0, omega};
    request.steady = {"q1", "q2", "q3"};
    request.driven = {"u4"};
    const io::ModesReport r = io::AnalyseModes(request);
    const double ramp = 1.0 - std::exp(-t / t0);
    for (int i = 0; i < 3; ++i) {
      const double theta = q4 + 2.0 * M_PI * i / 3.0;
      EXPECT_NEAR(r.steady->x(i), ramp * (f_w - m * g * std::sin(theta)) / (k - m * omega * omega),
                  1e-15) << "Ω = " << omega << ", blade " << i + 1;
    }
    EXPECT_EQ(r.steady->driven_speeds, std::vector<int>{3});
    request.driven.clear();
    EXPECT_THROW(io::AnalyseModes(request), ModelError);  // u̇4 = −d_g Ω / I_g ≠ 0
  }
}

TEST(SteadyStateTest, NoSteadyStateIsRefusedNamingTheResidual) {
  // k = 0 and T = 6 N·m > m g l = 4.905 N·m: u̇ ≥ (T − m g l)/(m l²) = 4.38 rad/s².
  try {
    Steady(kPendulum, {{"k", 0.0}, {"T", 6.0}}, "q");
    FAIL() << "no steady state exists";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no steady state found for q"), std::string::npos) << what;
    EXPECT_NE(what.find("4.38 rad/s²"), std::string::npos) << what;
    EXPECT_NE(what.find("Try another start"), std::string::npos) << what;
  }
}

TEST(SteadyStateTest, CommandLineRefusalsExitTwo) {
  struct Case {
    std::string args, says;
  };
  const Case cases[] = {
      {kPendulum + " --steady q --set k=0 --set T=6", "it has a minimum here that is not zero"},
      {kGovernor + " --steady psi", "no speed rate depends on coordinate psi"},
      {kGovernor + " --steady phi",
       "'phi' is not a coordinate of the model; its coordinates are psi, theta"},
      {kFourBar + " --steady q2 --at u=0,0,0", "coordinate q2 is dependent"},
      {kGovernor + " --steady theta --steady-iterations 1", "the iteration limit (1) was reached"},
      {kFourBar + " --steady q1 --driven u1",
       "driven speeds are supported for unconstrained models only"},
      {kGovernor + " --driven w", "driven speeds only matter for a steady state"},
      {kGovernor + " --steady theta --driven v",
       "'v' is not a speed of the model; its speeds are w, thetadot"},
  };
  for (const Case& c : cases) {
    const auto [status, out] = testing::RunCommand(
        fmt::format("{} modes {}", HYBRIDTEST_BINARY, c.args));
    EXPECT_EQ(status, 2) << c.args << "\n" << out;
    EXPECT_NE(out.find(c.says), std::string::npos) << c.args << "\n" << out;
  }
}

TEST(SteadyStateTest, CommandLineReportsIterationsAndResidual) {
  const auto [status, out] = testing::RunCommand(
      fmt::format("{} modes {} --steady theta --json", HYBRIDTEST_BINARY, kGovernor), 30, false);
  ASSERT_EQ(status, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["steady"]["coordinates"][0], "theta");
  EXPECT_NEAR(j["steady"]["values"][0].get<double>(), std::acos(9.81 / 20.0), 1e-10);
  EXPECT_GT(j["steady"]["iterations"].get<int>(), 0);
  EXPECT_LE(j["steady"]["residual"].get<double>(), 1e-10);
  EXPECT_EQ(j["steady"]["residual_unit"], "rad/s²");
  EXPECT_EQ(j["operating_point"][1].get<double>(), j["steady"]["values"][0].get<double>());
  const auto [text_status, text] = testing::RunCommand(
      fmt::format("{} modes {} --steady theta", HYBRIDTEST_BINARY, kGovernor));
  EXPECT_EQ(text_status, 0);
  EXPECT_NE(text.find("steady state (u̇ = 0) in "), std::string::npos) << text;
  EXPECT_NE(text.find("theta = 1.0581329042644"), std::string::npos) << text;
}

}  // namespace
}  // namespace hybridtest
