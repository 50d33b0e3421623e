// A constrained model compiled (issue 47 item 2, symbolic/codegen.h, compiled_model.h): its C
// defines the constraint rows (NAME_constraints), which give the engine's B, B u + c, f(q, t)
// and Ḃ u + ċ at random states; with the library attached the engine's constrained step reads
// them from it and its state derivative equals the engine's own at consistent states; a
// library whose constraint rows disagree with the model is refused, naming them.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <random>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/compiled_model.h"

namespace hybridtest::symbolic {
namespace {

void UseOwnCacheForConstraints() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = testing::TempDir() + "/compiled-constrained-" + info->name();
  std::filesystem::remove_all(dir);
  setenv("HYBRIDTEST_CACHE_DIR", dir.c_str(), 1);
  unsetenv("CC");
}

models::BuiltModel ConstrainedExample(const std::string& stem, double l0 = 0.0) {
  const auto file = modelfile::LoadModelFile(std::string(HYBRIDTEST_SOURCE_DIR) +
                                             "/examples/models/" + stem + ".yaml");
  models::ParameterSet parameters = file.parameters;
  if (l0 > 0.0) parameters.Set("l0", l0, "the test");
  return modelfile::BuildModelFile(file, parameters);
}

void ExpectClose(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const char* what) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a(i), b(i), 1e-12 * scale) << what << "[" << i << "]";
  }
}

// Counts the calls of the library's constraint rows (the engine must read them from there).
multibody::CompiledConstraintsFunction g_library_rows = nullptr;
int g_row_calls = 0;
void CountedRows(double t, const double* x, double* B, double* velocity, double* position,
                 double* bias) {
  ++g_row_calls;
  g_library_rows(t, x, B, velocity, position, bias);
}

void ExpectConstraintRowsEqualTheEngine(models::BuiltModel built) {
  multibody::Model& model = built.model;
  const int n = model.num_coordinates(), m = model.num_constraint_rows();
  ASSERT_GT(m, 0);
  const CCode code = WriteC(model, DeriveRhs(model), built.name, "f");
  EXPECT_NE(code.source.find("void f_constraints(double t, const double* x, double* B"),
            std::string::npos);
  EXPECT_NE(code.source.find("const int f_m = " + std::to_string(m) + ";"), std::string::npos);

  CompileReport report;
  const auto compiled = CompileModel(model, built.name, &report);
  ASSERT_NE(compiled->constraints, nullptr);
  EXPECT_LE(report.largest_difference, 1e-12);
  std::mt19937 rng(47);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  multibody::Data<double> data(model), data_compiled(model);
  Eigen::VectorXd x(model.num_states()), r = Eigen::VectorXd::Zero(model.num_slots());
  Eigen::VectorXd B(m * n), velocity(m), position(m), bias(m);
  Eigen::VectorXd xdot(model.num_states()), xdot_compiled(model.num_states());
  auto counted = std::make_shared<multibody::CompiledRhs>(*compiled);
  g_library_rows = compiled->constraints;
  counted->constraints = &CountedRows;
  for (int trial = 0; trial < 10; ++trial) {
    // The rows at any state: they are functions of t, q and u.
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = (i < n ? 1.0 : 4.0) * unit(rng);
    const double t = 5.0 * (1.0 + unit(rng));
    compiled->constraints(t, x.data(), B.data(), velocity.data(), position.data(), bias.data());
    multibody::CalcKinematics<double>(model, data, t, x);
    multibody::CalcConstraints<double>(model, data);
    ExpectClose(B, data.constraint_B.reshaped(), "B");
    ExpectClose(velocity, data.constraint_velocity, "B u + c");
    ExpectClose(position, data.constraint_position, "f(q, t)");
    ExpectClose(bias, data.constraint_bias, "bias");
    // The step at a consistent state, with the library attached and without.
    Eigen::VectorXd x0 = model.initial_state();
    x0(0) += 0.3 * unit(rng);
    x0(n) = 3.0 * unit(rng);
    const Eigen::VectorXd consistent = multibody::AssembleState(model, t, x0).x;
    model.AttachCompiledRhs(nullptr);
    multibody::CalcStateDerivative<double>(model, data, t, consistent, r, xdot);
    model.AttachCompiledRhs(counted);
    const int calls = g_row_calls;
    multibody::CalcStateDerivative<double>(model, data_compiled, t, consistent, r, xdot_compiled);
    model.AttachCompiledRhs(nullptr);
    EXPECT_EQ(g_row_calls, calls + 1) << "the step did not read the library's constraint rows";
    ExpectClose(xdot_compiled, xdot, "xdot");
  }
}

TEST(CompiledConstrainedModel, FourBarComputesItsConstraintRows) {
  UseOwnCacheForConstraints();
  ExpectConstraintRowsEqualTheEngine(ConstrainedExample("four_bar"));
}

TEST(CompiledConstrainedModel, SliderCrankComputesItsConstraintRows) {
  UseOwnCacheForConstraints();
  ExpectConstraintRowsEqualTheEngine(ConstrainedExample("slider_crank"));
}

// Another ground link moves only the loop's closure point: M, g and B are the same, f(q, t)
// is not. The four-bar's library loaded for it is refused, naming the constraint positions.
TEST(CompiledConstrainedModel, LoadRefusesALibraryWhoseConstraintRowsDiffer) {
  UseOwnCacheForConstraints();
  CompileReport report;
  CompileModel(ConstrainedExample("four_bar").model, "four_bar", &report);
  try {
    LoadCompiledModel(ConstrainedExample("four_bar", 0.35).model, report.library);
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("disagrees with the numeric engine in the constraint positions"),
              std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hybridtest::symbolic
