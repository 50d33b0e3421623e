// A constrained model's printed equations (issue 47 item 2, symbolic/constrained.h): the
// reduced equations, with A solved from A_d A = −A_i at a consistent state, equal the engine's
// CalcReducedEquations there. (Its C form: codegen_test.cc.)
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <string>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/equations.h"

namespace hybridtest::symbolic {
namespace {

multibody::Model FourBar() {
  const auto file = modelfile::LoadModelFile(
      std::string(HYBRIDTEST_SOURCE_DIR "/examples/models/four_bar.yaml"));
  return modelfile::BuildModelFile(file, file.parameters).model;
}

double ValueAt(const Equations& eq, const GiNaC::ex& e, const GiNaC::exmap& state) {
  const GiNaC::ex v = GiNaC::evalf(Inline(eq.shared, e).subs(state));
  EXPECT_TRUE(GiNaC::is_a<GiNaC::numeric>(v)) << "not a number at the state: " << v;
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

TEST(ConstrainedEquations, FourBarReducedEquationsEqualTheEngines) {
  const multibody::Model model = FourBar();
  const Equations eq = DeriveEquations(model);
  const int n = model.num_coordinates();
  const int m = model.num_constraint_rows();
  const int p = n - m;
  ASSERT_EQ(eq.constrained.dependent, (std::vector<int>{1, 2}));  // the file's u2, u3
  ASSERT_EQ(static_cast<int>(eq.constrained.M.size()), n);
  const double t = 0.4;
  Eigen::VectorXd x0 = model.initial_state();
  x0(n) = 1.3;  // the crank's rate [rad/s]
  const Eigen::VectorXd x = multibody::AssembleState(model, t, x0).x;
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(model.num_states());
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(model.num_slots());
  multibody::CalcStateDerivative<double>(model, data, t, x, r, xdot);
  multibody::CalcReducedEquations(model, data, false);
  ASSERT_EQ(data.dependent, eq.constrained.dependent);

  GiNaC::exmap state = {{eq.t, t}};
  for (int k = 0; k < n; ++k) {
    state[eq.q[static_cast<std::size_t>(k)]] = x(k);
    state[eq.u[static_cast<std::size_t>(k)]] = x(n + k);
  }
  Eigen::MatrixXd Ad(m, m), Ai(m, p);
  for (int s = 0; s < m; ++s) {
    const auto row = static_cast<std::size_t>(s);
    for (int k = 0; k < m; ++k) Ad(s, k) = ValueAt(eq, eq.constrained.A_d[row][static_cast<std::size_t>(k)], state);
    for (int c = 0; c < p; ++c) Ai(s, c) = ValueAt(eq, eq.constrained.A_i[row][static_cast<std::size_t>(c)], state);
    // The printed row vanishes at the consistent state.
    double residual = ValueAt(eq, eq.constrained.b[row], state);
    for (int k = 0; k < m; ++k) residual += Ad(s, k) * x(n + eq.constrained.dependent[static_cast<std::size_t>(k)]);
    for (int c = 0; c < p; ++c) residual += Ai(s, c) * x(n + eq.constrained.independent[static_cast<std::size_t>(c)]);
    EXPECT_NEAR(residual, 0.0, 1e-9) << eq.constrained.rows[row];
  }
  const Eigen::MatrixXd A = -Ad.lu().solve(Ai);
  for (int s = 0; s < m; ++s)
    for (int c = 0; c < p; ++c) state[eq.constrained.A[static_cast<std::size_t>(s)][static_cast<std::size_t>(c)]] = A(s, c);
  const double scale = std::max({1.0, data.reduced_M.cwiseAbs().maxCoeff(), data.reduced_f.cwiseAbs().maxCoeff()});
  for (int j = 0; j < n; ++j) {
    const auto row = static_cast<std::size_t>(j);
    for (int k = 0; k < n; ++k) {
      EXPECT_NEAR(ValueAt(eq, eq.constrained.M[row][static_cast<std::size_t>(k)], state),
                  data.reduced_M(j, k), 1e-12 * scale) << "M_r[" << j << "," << k << "]";
    }
    EXPECT_NEAR(ValueAt(eq, eq.constrained.f[row], state), data.reduced_f(j), 1e-12 * scale)
        << "f_r[" << j << "]";
  }
}

}  // namespace
}  // namespace hybridtest::symbolic
