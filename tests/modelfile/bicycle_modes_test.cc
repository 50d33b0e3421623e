// The benchmark bicycle (examples/models/whipple_bicycle.yaml) against Meijaard,
// Papadopoulos, Ruina and Schwab (2007): `hybridtest modes --set v=V --json` gives the
// eigenvalues of their Table 2 for V = 0, 1, …, 10 m/s within 1e-9 relative (the other six
// eigenvalues, of the ignorable states, are zero), and a scan of the linearisation finds the
// weave and capsize speeds of Table 2a within 1e-8 m/s.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <complex>
#include <nlohmann/json.hpp>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/modes.h"
#include "support/run_command.h"

namespace hybridtest {
namespace {

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kModel = kSource + "/examples/models/whipple_bicycle.yaml";

// Table 2: weave pair (re, ±im), capsize, castering; at v = 0 the "weave pair" is real.
struct Row {
  double re, im, capsize, castering;
};
const Row kTable2[] = {
    {3.13164324790656, 0.0, -3.13164324790656, -5.53094371765393},  // plus 5.53094371765393
    {3.52696170990070, 0.80774027519930, -3.13423125066578, -7.11008014637442},
    {2.68234517512745, 1.68066296590675, -3.07158645641514, -8.67387984831735},
    {1.70675605663975, 2.31582447384325, -2.63366137253667, -10.35101467245920},
    {0.41325331521125, 3.07910818603206, -1.42944427361326, -12.15861426576450},
    {-0.77534188219585, 4.46486771378823, -0.32286642900409, -14.07838969279820},
    {-1.52644486584142, 5.87673060598709, -0.00406690076970, -16.08537123098030},
    {-2.13875644258362, 7.19525913329805, 0.10268170574766, -18.15788466125262},
    {-2.69348683581097, 8.46037971396931, 0.14327879765713, -20.27940894394569},
    {-3.21675402252485, 9.69377351531791, 0.15790184030917, -22.43788559040858},
    {-3.72016840437287, 10.90681139476287, 0.16105338653172, -24.62459635017404},
};

TEST(BicycleModesTest, ModesCommandGivesTable2) {
  for (int v = 0; v <= 10; ++v) {
    const auto [status, out] = testing::RunCommand(
        fmt::format("{} modes {} --set v={} --json", HYBRIDTEST_BINARY, kModel, v), 120, false);
    ASSERT_EQ(status, 0) << out;
    const nlohmann::json j = nlohmann::json::parse(out);
    std::vector<std::complex<double>> got;
    for (const auto& m : j["modes"]) got.emplace_back(m["real"].get<double>(), m["imag"].get<double>());
    ASSERT_EQ(got.size(), 10u);
    const Row& row = kTable2[v];
    std::vector<std::complex<double>> want = {{row.re, row.im}, {row.re, -row.im},
                                              {row.capsize, 0.0}, {row.castering, 0.0}};
    if (v == 0) want[1] = {5.53094371765393, 0.0};
    for (const auto& w : want) {
      double best = 1e300;
      for (const auto& g : got) best = std::min(best, std::abs(g - w));
      EXPECT_LE(best, 1e-9 * std::abs(w)) << "v = " << v << ", λ = " << w;
    }
    int zeros = 0;
    for (const auto& g : got) zeros += std::abs(g) < 1e-9 ? 1 : 0;
    EXPECT_EQ(zeros, 6) << "v = " << v;
  }
}

// The roll–steer block of the state matrix (q4, q7, u4, u7) at speed v: its eigenvalues are
// Table 2's (the ignorable states do not feed back).
Eigen::Matrix4d RollSteerBlock(const modelfile::ModelFile& file, double v) {
  models::ParameterSet p = file.parameters;
  p.Set("v", v, "test");
  const models::BuiltModel built = modelfile::BuildModelFile(file, p);
  const multibody::ModeAnalysis a =
      multibody::CalcModes(built.model, 0.0, built.model.initial_state(), {});
  const auto& names = a.linearization.state_names;
  std::vector<int> at;
  for (const char* s : {"q4", "q7", "u4", "u7"}) {
    at.push_back(static_cast<int>(std::find(names.begin(), names.end(), s) - names.begin()));
  }
  Eigen::Matrix4d A;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) A(i, k) = a.linearization.A(at[i], at[k]);
  return A;
}

double WeaveRealPart(const modelfile::ModelFile& file, double v) {
  const Eigen::Vector4cd l = Eigen::EigenSolver<Eigen::Matrix4d>(RollSteerBlock(file, v)).eigenvalues();
  double re = -1e300;
  for (int i = 0; i < 4; ++i)
    if (std::abs(l(i).imag()) > 1e-6) re = std::max(re, l(i).real());
  return re;
}

double CapsizeDeterminant(const modelfile::ModelFile& file, double v) {
  return RollSteerBlock(file, v).determinant();  // the product of the four eigenvalues
}

// A root of f in [a, b] (f(a), f(b) of opposite signs) by the secant–bisection of Dekker.
template <class F>
double Root(F f, double a, double b) {
  double fa = f(a), fb = f(b);
  EXPECT_LT(fa * fb, 0.0);
  for (int i = 0; i < 100 && b - a > 1e-13; ++i) {
    double m = b - fb * (b - a) / (fb - fa);
    if (!(m > a && m < b) || i % 3 == 2) m = 0.5 * (a + b);
    const double fm = f(m);
    if (fm == 0.0) return m;
    if ((fm < 0) == (fa < 0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
      fb = fm;
    }
  }
  return 0.5 * (a + b);
}

TEST(BicycleModesTest, ScanFindsTheWeaveAndCapsizeSpeeds) {
  const modelfile::ModelFile file = modelfile::LoadModelFile(kModel);
  const double weave = Root([&](double v) { return WeaveRealPart(file, v); }, 4.0, 5.0);
  const double capsize = Root([&](double v) { return CapsizeDeterminant(file, v); }, 5.5, 6.5);
  EXPECT_NEAR(weave, 4.29238253634111, 1e-8);
  EXPECT_NEAR(capsize, 6.02426201538837, 1e-8);
}

}  // namespace
}  // namespace hybridtest
