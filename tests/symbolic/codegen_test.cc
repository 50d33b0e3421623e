// Generated C (issue 36 item 3): compiled by the system C compiler and loaded, it gives the
// numeric engine's M, g, q̇ and ż at random states for the rotor and every example model file;
// the engine's state derivative with it attached equals the engine's own; every common
// subexpression is computed once; the cache is reused; stale libraries and a missing compiler
// are refused with errors that say so. A constrained model's C (issue 47 item 2) defines the
// constraint rows (NAME_constraints), which give the engine's B, B u + c, f(q, t) and Ḃ u + ċ
// at random states; with the library attached the engine's constrained step reads them from
// it and its state derivative equals the engine's own at consistent states; a library whose
// constraint rows disagree with the model is refused, naming them.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <random>
#include <regex>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/compiled_model.h"

namespace hybridtest::symbolic {
namespace {

// A cache of compiled models of this test's own (tests run in parallel processes).
void UseOwnCache() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = testing::TempDir() + "/compiled-" + info->name();
  std::filesystem::remove_all(dir);
  setenv("HYBRIDTEST_CACHE_DIR", dir.c_str(), 1);
  unsetenv("CC");
}

models::BuiltModel Rotor(double m_b = 1.96) {
  models::ParameterSet p = models::DefaultParameters("rotor", 3);
  p.Set("m_b", m_b, "the test");
  return models::BuildModel("rotor", 3, p);
}

// An example model file, with the parameter `name` (if given) set to `value`.
models::BuiltModel ExampleFile(const std::string& stem, const char* name = nullptr,
                               double value = 0.0) {
  const auto file = modelfile::LoadModelFile(std::string(HYBRIDTEST_SOURCE_DIR) +
                                             "/examples/models/" + stem + ".yaml");
  models::ParameterSet parameters = file.parameters;
  if (name != nullptr) parameters.Set(name, value, "the test");
  return modelfile::BuildModelFile(file, parameters);
}

void ExpectNear(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const char* what) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a(i), b(i), 1e-12 * scale) << what << "[" << i << "]";
  }
}

void ExpectCompiledEqualsEngine(models::BuiltModel built, int trials) {
  multibody::Model& model = built.model;
  CompileReport report;
  auto compiled = CompileModel(model, built.name, &report);
  EXPECT_FALSE(report.from_cache);
  EXPECT_LE(report.largest_difference, 1e-12);
  const int n = model.num_coordinates(), nz = model.num_extra_states();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0), speed(-4.0, 4.0),
      force(-2000.0, 2000.0), time(0.0, 10.0);
  multibody::Data<double> data(model), data_compiled(model);
  Eigen::VectorXd x(model.num_states()), r(model.num_slots()), M(n * n), g(n), qdot(n),
      zdot(nz), xdot(model.num_states()), xdot_compiled(model.num_states());
  for (int trial = 0; trial < trials; ++trial) {
    for (int k = 0; k < n; ++k) x(k) = coordinate(rng), x(n + k) = speed(rng);
    for (int k = 0; k < nz; ++k) x(2 * n + k) = coordinate(rng);
    for (int s = 0; s < model.num_slots(); ++s) r(s) = force(rng);
    const double t = time(rng);
    compiled->function(t, x.data(), r.data(), M.data(), g.data(), qdot.data(), zdot.data());
    multibody::CalcKinematics<double>(model, data, t, x);
    multibody::CalcMassMatrix<double>(model, data);
    multibody::CalcForcing<double>(model, data, r);
    ExpectNear(M, data.M.reshaped(), "M");
    ExpectNear(g, data.g, "g");
    ExpectNear(qdot, data.qdot, "qdot");
    // The whole state derivative (ż included) with the library attached and without.
    model.AttachCompiledRhs(nullptr);
    multibody::CalcStateDerivative<double>(model, data, t, x, r, xdot);
    model.AttachCompiledRhs(compiled);
    multibody::CalcStateDerivative<double>(model, data_compiled, t, x, r, xdot_compiled);
    model.AttachCompiledRhs(nullptr);
    ExpectNear(xdot_compiled, xdot, "xdot");
  }
}

TEST(CompiledModel, RotorEqualsTheEngine) {
  UseOwnCache();
  ExpectCompiledEqualsEngine(Rotor(), 25);
}

TEST(CompiledModel, ExampleModelFilesEqualTheEngine) {
  UseOwnCache();
  for (const char* stem : {"cart_pendulum", "double_pendulum", "rotor", "spinning_top",
                           "wind_turbine"}) {
    SCOPED_TRACE(stem);
    ExpectCompiledEqualsEngine(ExampleFile(stem), 25);
  }
}

TEST(CompiledModel, EveryCommonSubexpressionIsComputedOnce) {
  const auto built = ExampleFile("wind_turbine");
  const CCode code = WriteC(built.model, DeriveRhs(built.model), built.name, "f");
  const std::regex temporary(R"(  const double t(\d+) = (.*);)");
  std::set<std::string> values;
  int count = 0;
  for (auto it = std::sregex_iterator(code.source.begin(), code.source.end(), temporary);
       it != std::sregex_iterator(); ++it) {
    ++count;
    EXPECT_EQ(std::stoi((*it)[1]), count) << "temporaries are numbered in order of definition";
    EXPECT_TRUE(values.insert((*it)[2]).second) << "computed twice: " << (*it)[2];
  }
  EXPECT_EQ(count, code.temporaries);
  EXPECT_GT(count, 50);
  EXPECT_EQ(code.source.find("#include"), code.source.find("#include <math.h>"));
}

TEST(CompiledModel, CacheIsReusedAndStaleLibrariesAreRefused) {
  UseOwnCache();
  CompileReport first, second;
  CompileModel(Rotor().model, "rotor", &first);
  CompileModel(Rotor().model, "rotor", &second);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(first.library, second.library);
  EXPECT_EQ(std::filesystem::path(first.library).parent_path(), CompiledModelCacheDir());
  // Another parameter value is another source, so another library.
  CompileReport heavier;
  CompileModel(Rotor(2.5).model, "rotor", &heavier);
  EXPECT_NE(heavier.library, first.library);
  // The rotor's library loaded for a rotor with another blade mass, or for another model.
  try {
    LoadCompiledModel(Rotor(2.5).model, first.library);
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("disagrees with the numeric engine"), std::string::npos)
        << e.what();
  }
  try {
    LoadCompiledModel(ExampleFile("double_pendulum").model, first.library);
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("compiled for another model"), std::string::npos)
        << e.what();
  }
}

TEST(CompiledModel, MissingCompilerIsANamedError) {
  UseOwnCache();
  setenv("CC", "/nonexistent/hybridtest-cc", 1);
  try {
    CompileModel(Rotor().model, "rotor");
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("C compiler '/nonexistent/hybridtest-cc'"),
              std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("set CC"), std::string::npos) << e.what();
  }
  unsetenv("CC");
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
    ExpectNear(B, data.constraint_B.reshaped(), "B");
    ExpectNear(velocity, data.constraint_velocity, "B u + c");
    ExpectNear(position, data.constraint_position, "f(q, t)");
    ExpectNear(bias, data.constraint_bias, "bias");
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
    ExpectNear(xdot_compiled, xdot, "xdot");
  }
}

TEST(CompiledConstrainedModel, FourBarComputesItsConstraintRows) {
  UseOwnCache();
  ExpectConstraintRowsEqualTheEngine(ExampleFile("four_bar"));
}

TEST(CompiledConstrainedModel, SliderCrankComputesItsConstraintRows) {
  UseOwnCache();
  ExpectConstraintRowsEqualTheEngine(ExampleFile("slider_crank"));
}

// Another ground link moves only the loop's closure point: M, g and B are the same, f(q, t)
// is not. The four-bar's library loaded for it is refused, naming the constraint positions.
TEST(CompiledConstrainedModel, LoadRefusesALibraryWhoseConstraintRowsDiffer) {
  UseOwnCache();
  CompileReport report;
  CompileModel(ExampleFile("four_bar").model, "four_bar", &report);
  try {
    LoadCompiledModel(ExampleFile("four_bar", "l0", 0.35).model, report.library);
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("disagrees with the numeric engine in the constraint positions"),
              std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hybridtest::symbolic
