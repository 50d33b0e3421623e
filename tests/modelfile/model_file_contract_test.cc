// Issue 19's contract for model files: units are converted to SI or refused, required keys are
// required (with file:line), inertias are physical, constant angles beyond a turn are refused
// as probable degrees, and the places of errors that used to be lost are named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// A pendulum of length L with a bob and a rod body; `L_line` replaces line 3.
std::string Pendulum(const std::string& L_line, const std::string& rest = "") {
  return "name: p\n"                                                    // 1
         "parameters:\n"                                                // 2
         + L_line + "\n" +                                              // 3
         "coordinates:\n"                                               // 4
         "  - {name: th, unit: rad}\n"                                  // 5
         "  - {name: x, unit: m}\n"                                     // 6
         "frames:\n"                                                    // 7
         "  - {name: A, parent: N, axis: z, angle: th}\n"               // 8
         "points:\n"                                                    // 9
         "  - {name: C, from: O, frame: N, position: [0, x, 0]}\n"      // 10
         "  - {name: P, from: C, frame: A, position: [L, 0, 0]}\n"      // 11
         "particles:\n"                                                 // 12
         "  - {name: bob, point: P, mass: 0.8}\n"                       // 13
         "bodies:\n"                                                    // 14
         "  - {name: cart, frame: A, mass_center: C, mass: 3, inertia: [0.1, 0.1, 0.2]}\n"  // 15
         + rest;
}

models::BuiltModel Build(const std::string& text) {
  const ModelFile f = ParseModelFile(YamlInput::FromText(text, "m.yaml"));
  return BuildModelFile(f, f.parameters);
}

std::string ErrorOf(const std::string& text) {
  try {
    Build(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

Eigen::MatrixXd MassMatrix(const models::BuiltModel& b, const Eigen::VectorXd& x) {
  multibody::Data<double> data(b.model);
  multibody::CalcKinematics<double>(b.model, data, 0.0, x);
  multibody::CalcMassMatrix<double>(b.model, data);
  return data.M;
}

TEST(ModelFileContractTest, LabUnitsGiveTheSameModelAsSI) {
  const models::BuiltModel si = Build(Pendulum("  L: 0.6"));
  const models::BuiltModel mm = Build(Pendulum("  L: {value: 600, unit: mm, description: rod}"));
  const models::BuiltModel cm = Build(Pendulum("  L: {value: 60, unit: cm}"));
  EXPECT_DOUBLE_EQ(mm.parameters.Get("L"), 0.6);
  EXPECT_EQ(mm.parameters.all()[0].unit, "m");
  EXPECT_THAT(mm.parameters.all()[0].description, HasSubstr("given as 600 mm"));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-2, 2);
  for (int i = 0; i < 5; ++i) {
    Eigen::VectorXd x(4);
    x << d(rng), d(rng), d(rng), d(rng);
    const Eigen::MatrixXd M = MassMatrix(si, x);
    EXPECT_LT((MassMatrix(mm, x) - M).cwiseAbs().maxCoeff(), 1e-14 * M.cwiseAbs().maxCoeff());
    EXPECT_LT((MassMatrix(cm, x) - M).cwiseAbs().maxCoeff(), 1e-14 * M.cwiseAbs().maxCoeff());
  }
  // The bob's M entry: m L² = 0.8 · 0.36 (not 0.8 · 600²).
  EXPECT_NEAR(MassMatrix(mm, Eigen::VectorXd::Zero(4))(0, 0), 0.8 * 0.36 + 0.2, 1e-14);
}

TEST(ModelFileContractTest, UnknownAndLabStateUnitsAreRefusedWithTheFix) {
  EXPECT_THAT(ErrorOf(Pendulum("  L: {value: 600, unit: milimetre}")),
              AllOf(HasSubstr("m.yaml:3: parameters.L.unit"), HasSubstr("'milimetre'"),
                    HasSubstr("known:")));
  std::string coordinate_mm = Pendulum("  L: 0.6");
  coordinate_mm.replace(coordinate_mm.find("{name: x, unit: m}"), 18, "{name: x, unit: mm}");
  EXPECT_THAT(ErrorOf(coordinate_mm), AllOf(HasSubstr("m.yaml:6: coordinates[1].unit"),
                                            HasSubstr("write `unit: m`")));
  std::string coordinate_deg = Pendulum("  L: 0.6");
  coordinate_deg.replace(coordinate_deg.find("{name: th, unit: rad}"), 21, "{name: th, unit: deg}");
  EXPECT_THAT(ErrorOf(coordinate_deg), AllOf(HasSubstr("coordinates[0].unit"), HasSubstr("rad")));
  std::string coordinate_force = Pendulum("  L: 0.6");
  coordinate_force.replace(coordinate_force.find("{name: x, unit: m}"), 18, "{name: x, unit: N}");
  EXPECT_THAT(ErrorOf(coordinate_force), HasSubstr("a length (m), an angle (rad)"));
}

TEST(ModelFileContractTest, AnglesInDegreesAreExplicit) {
  std::string deg = Pendulum("  L: 0.6", "frames2: 1\n");
  EXPECT_THAT(ErrorOf(deg), HasSubstr("frames2"));
  std::string thirty = Pendulum("  L: 0.6");
  thirty.replace(thirty.find("angle: th}"), 10, "angle: 30}");
  EXPECT_THAT(ErrorOf(thirty), AllOf(HasSubstr("m.yaml:8: frames[0].angle"),
                                     HasSubstr("write `30 deg`")));
  std::string explicit_deg = Pendulum("  L: 0.6");
  explicit_deg.replace(explicit_deg.find("angle: th}"), 10, "angle: th + 30 deg}");
  std::string radians = Pendulum("  L: 0.6");
  radians.replace(radians.find("angle: th}"), 10, "angle: th + pi / 6}");
  Eigen::VectorXd x(4);
  x << 0.3, 0.1, 0.5, -0.2;
  EXPECT_LT((MassMatrix(Build(explicit_deg), x) - MassMatrix(Build(radians), x)).cwiseAbs().maxCoeff(),
            1e-14);
}

TEST(ModelFileContractTest, RequiredKeysAreRequiredWithFileAndLine) {
  std::string no_mass = Pendulum("  L: 0.6");
  no_mass.replace(no_mass.find("mass: 3, "), 9, "");
  EXPECT_THAT(ErrorOf(no_mass), AllOf(HasSubstr("m.yaml:15: bodies[0].mass: missing"),
                                      HasSubstr("add `mass: ...`")));
  std::string no_inertia = Pendulum("  L: 0.6");
  no_inertia.replace(no_inertia.find(", inertia: [0.1, 0.1, 0.2]"), 26, "");
  EXPECT_THAT(ErrorOf(no_inertia), AllOf(HasSubstr("m.yaml:15: bodies[0].inertia: missing"),
                                         HasSubstr("[0, 0, 0] for none")));
  std::string no_particle_mass = Pendulum("  L: 0.6");
  no_particle_mass.replace(no_particle_mass.find(", mass: 0.8"), 11, "");
  EXPECT_THAT(ErrorOf(no_particle_mass), HasSubstr("m.yaml:13: particles[0].mass: missing"));
  std::string no_position = Pendulum("  L: 0.6");
  no_position.replace(no_position.find(", position: [L, 0, 0]"), 21, "");
  EXPECT_THAT(ErrorOf(no_position), HasSubstr("m.yaml:11: points[1].position: missing"));
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "forces:\n  - {name: f, point: P}\n")),
              HasSubstr("m.yaml:17: forces[0].value: missing"));
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "slots:\n  - {name: r1, unit: N, displacement: x}\n")),
              AllOf(HasSubstr("m.yaml:17: slots[0].stiffness: missing"),
                    HasSubstr("`stiffness: 0` for none")));
  // Written as 0, a zero stiffness is accepted.
  const models::BuiltModel zero = Build(
      Pendulum("  L: 0.6", "slots:\n  - {name: r1, unit: N, displacement: x, stiffness: 0}\n"));
  EXPECT_EQ(zero.slot_stiffness.at(0), 0.0);
  // An unquoted formula with a comma inside [...] is split by YAML: say so.
  std::string pow = Pendulum("  L: 0.6");
  pow.replace(pow.find("[L, 0, 0]"), 9, "[pow(L, 2), 0, 0]");
  EXPECT_THAT(ErrorOf(pow), AllOf(HasSubstr("points[1].position"), HasSubstr("must be quoted")));
  std::string quoted = Pendulum("  L: 0.6");
  quoted.replace(quoted.find("[L, 0, 0]"), 9, "[\"pow(L, 2)\", 0, 0]");
  EXPECT_EQ(ErrorOf(quoted), "no error");
}

TEST(ModelFileContractTest, InertiasMustBePhysical) {
  auto with = [](const std::string& inertia) {
    std::string s = Pendulum("  L: 0.6");
    s.replace(s.find("[0.1, 0.1, 0.2]"), 15, inertia);
    return ErrorOf(s);
  };
  EXPECT_THAT(with("[0, 0, 1]"), AllOf(HasSubstr("m.yaml:15: bodies[0].inertia"),
                                       HasSubstr("triangle inequality"),
                                       HasSubstr("[I_zz/2, I_zz/2, I_zz]")));
  EXPECT_THAT(with("[0.1, -0.1, 0.1]"), HasSubstr("negative"));
  EXPECT_THAT(with("[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]"), HasSubstr("not symmetric"));
  EXPECT_EQ(with("[0, 0, 0]"), "no error");       // a point mass
  EXPECT_EQ(with("[0, 0.5, 0.5]"), "no error");   // a slender rod: equality
  EXPECT_EQ(with("[0.25, 0.25, 0.5]"), "no error");  // a thin disc: equality
  EXPECT_EQ(with("[[2, 0.5, 0], [0.5, 2, 0], [0, 0, 3]]"), "no error");
  EXPECT_THAT(with("[pow(L, 2), 1, 1]"), AllOf(HasSubstr("bodies[0].inertia"), HasSubstr("must be quoted")));
  EXPECT_EQ(with("[\"pow(L, 2)\", 0.3, 0.3]"), "no error");
}

TEST(ModelFileContractTest, SlotInAPositionSaysWhereSlotsGo) {
  std::string s = Pendulum("  L: 0.6", "slots:\n  - {name: r1, unit: N, displacement: x, stiffness: 5}\n");
  s.replace(s.find("[L, 0, 0]"), 9, "[L + r1, 0, 0]");
  EXPECT_THAT(ErrorOf(s), AllOf(HasSubstr("points[1].position[0]"), HasSubstr("'r1' is a slot")));
}

TEST(ModelFileContractTest, TablesAreCheckedWhereTheyAreDeclared) {
  auto with = [](const std::string& tables) { return ErrorOf(Pendulum("  L: 0.6", tables)); };
  EXPECT_EQ(with("tables:\n  f: {x: [0, 1 m], y: [0, L]}\nforces:\n  - {name: a, point: P, value: [f(x), 0, 0]}\n"),
            "no error");
  EXPECT_THAT(with("tables:\n  f: {x: [0, 2, 1], y: [0, 1, 2]}\n"),
              AllOf(HasSubstr("m.yaml:17: tables.f.x[2]"), HasSubstr("increase strictly")));
  EXPECT_THAT(with("tables:\n  f: {x: [0, 1, 2], y: [0, 1]}\n"), HasSubstr("as many y as x"));
  EXPECT_THAT(with("tables:\n  f: {x: [0, 1]}\n"), HasSubstr("m.yaml:17: tables.f.y: missing"));
  EXPECT_THAT(with("tables:\n  sin: {x: [0, 1], y: [0, 1]}\n"), HasSubstr("built-in function"));
  EXPECT_THAT(with("tables:\n  L: {x: [0, 1], y: [0, 1]}\n"), HasSubstr("already used"));
  EXPECT_THAT(with("tables:\n  f: {x: [0, th], y: [0, 1]}\n"), HasSubstr("a constant"));
  EXPECT_THAT(with("tables:\n  f: {x: [0, 1], y: [0, 1, 2], z: [[0, 1, 2]]}\n"),
              AllOf(HasSubstr("tables.f.z"), HasSubstr("2 rows (one per x) of 3 values")));
  EXPECT_THAT(with("tables:\n  f: {x: [0, 1], y: [0, 1], z: [[0, 1], [2]]}\n"),
              HasSubstr("tables.f.z[1]"));
  EXPECT_THAT(with("tables:\n  f: {x: [0, 1], y: [1, 0], z: [[0, 1], [2, 3]]}\n"),
              HasSubstr("y must increase strictly"));
  EXPECT_EQ(with("tables:\n  f: {x: [0, 1], y: [0, 1], z: [[0, 1], [2, 3]]}\n"
                 "forces:\n  - {name: a, point: P, value: [\"f(x, th)\", 0, 0]}\n"), "no error");
}

TEST(ModelFileContractTest, RepeatExpandsToTheSameModelAsTheCopies) {
  const ModelFile copies = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/rotor.yaml");
  const ModelFile repeat = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/tests/modelfile/data/rotor_repeat.yaml");
  const models::BuiltModel a = BuildModelFile(copies, copies.parameters);
  const models::BuiltModel b = BuildModelFile(repeat, repeat.parameters);
  ASSERT_EQ(b.model.num_slots(), 3);
  EXPECT_EQ(b.model.slots()[2].info.name, "r3");
  EXPECT_EQ(b.model.slots()[1].info.description, "static restoring force of blade 2");
  EXPECT_EQ(b.model.loads().size(), a.model.loads().size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1, 1);
  for (int i = 0; i < 5; ++i) {
    Eigen::VectorXd x(8), r(3);
    for (int k = 0; k < 8; ++k) x(k) = d(rng);
    for (int k = 0; k < 3; ++k) r(k) = 100 * d(rng);
    multibody::Data<double> da(a.model), db(b.model);
    Eigen::VectorXd xa(8), xb(8);
    multibody::CalcStateDerivative<double>(a.model, da, 0.3, x, r, xa);
    multibody::CalcStateDerivative<double>(b.model, db, 0.3, x, r, xb);
    EXPECT_EQ(xa, xb);  // the same model, bit for bit
  }
}

TEST(ModelFileContractTest, RepeatErrorsNameTheExpandedElement) {
  const std::string rest =
      "slots:\n"                                                              // 16
      "  - repeat: {i: [1, 2]}\n"                                             // 17
      "    items:\n"                                                          // 18
      "      - {name: r$i, unit: N, displacement: x, stiffness: k$i}\n";      // 19
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6\n  k1: 5", rest)),
              AllOf(HasSubstr("m.yaml:20: slots[0].items[0] (i = 2).stiffness"),
                    HasSubstr("'k2'")));
  EXPECT_EQ(ErrorOf(Pendulum("  L: 0.6\n  k1: 5\n  k2: 6", rest)), "no error");
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "slots:\n  - repeat: {i: 3}\n    items: []\n")),
              HasSubstr("{i: [1, 2, 3]}"));
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "slots:\n  - repeat: {i: [1]}\n    items:\n"
                                          "      - repeat: {j: [1]}\n        items: []\n")),
              HasSubstr("do not nest"));
}

TEST(ModelFileContractTest, TheJetCapNamesTheNonAffineExpression) {
  std::string s = "name: chain\ncoordinates:\n";                    // 1-2
  for (int k = 1; k <= 33; ++k) s += fmt::format("  - {{name: q{}, unit: m}}\n", k);  // 3-35
  s += "points:\n";                                                 // 36
  for (int k = 1; k <= 33; ++k) {
    s += fmt::format("  - {{name: P{0}, position: [{1}, 0, 0]}}\n", k,
                     k == 20 ? "0.1 * sin(10 * q20)" : fmt::format("q{}", k));  // P20 on line 56
  }
  s += "particles:\n";
  for (int k = 1; k <= 33; ++k) s += fmt::format("  - {{name: m{0}, point: P{0}, mass: 1}}\n", k);
  EXPECT_THAT(ErrorOf(s), AllOf(HasSubstr("at most 32"),
                                HasSubstr("m.yaml:56: points[19].position[0] = '0.1 * sin(10 * q20)'")));
}

// The exact state Jacobian and coupling matrix (AutoDiff) stay exact through the new functions,
// tables and velocity(): against central differences of the double right-hand side.
TEST(ModelFileContractTest, JacobianAndCouplingStayExactThroughFunctionsTablesAndVelocities) {
  for (const std::string name : {"turbine_functions", "top_drag"}) {
    SCOPED_TRACE(name);
    const ModelFile f = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/tests/modelfile/data/" + name + ".yaml");
    const models::BuiltModel b = BuildModelFile(f, f.parameters);
    const int n = b.model.num_coordinates(), ns = b.model.num_slots();
    const int nx = b.model.num_states();  // [q; u; z]: the extra states' columns too
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> d(-0.5, 0.5);
    Eigen::VectorXd x(nx), r = Eigen::VectorXd::Constant(ns, 30.0);
    for (int k = 0; k < nx; ++k) x(k) = d(rng);
    x(n + 1) += 2.0;  // away from the kinks of if(), sign() and the tables' knots
    multibody::Data<double> data(b.model);
    auto f_rhs = [&](const Eigen::VectorXd& xx, const Eigen::VectorXd& rr) {
      Eigen::VectorXd out(nx);
      multibody::CalcStateDerivative<double>(b.model, data, 0.7, xx, rr, out);
      return out;
    };
    const Eigen::MatrixXd J = multibody::CalcStateJacobian(b.model, 0.7, x, r);
    const double h = 1e-6;
    for (int k = 0; k < nx; ++k) {
      Eigen::VectorXd xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      const Eigen::VectorXd fd = (f_rhs(xp, r) - f_rhs(xm, r)) / (2 * h);
      EXPECT_LT((J.col(k) - fd).cwiseAbs().maxCoeff(), 1e-5 * (1.0 + fd.cwiseAbs().maxCoeff()))
          << "column " << k;
    }
    if (ns > 0) {
      const Eigen::MatrixXd B = multibody::CalcCouplingMatrix(b.model, 0.7, x);
      multibody::Data<double> dd(b.model);
      multibody::CalcKinematics<double>(b.model, dd, 0.7, x);
      multibody::CalcForcing<double>(b.model, dd, Eigen::VectorXd::Zero(ns));
      const Eigen::VectorXd g0 = dd.g;
      multibody::CalcForcing<double>(b.model, dd, Eigen::VectorXd::Unit(ns, 0));
      EXPECT_LT((B.col(0) - (dd.g - g0)).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

TEST(ModelFileContractTest, VelocitiesAreForLoadsOnly) {
  std::string s = Pendulum("  L: 0.6");
  s.replace(s.find("[L, 0, 0]"), 9, "[\"L + velocity(C, N).x\", 0, 0]");
  EXPECT_THAT(ErrorOf(s), AllOf(HasSubstr("points[1].position[0]"), HasSubstr("only in forces and torques")));
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "forces:\n  - {name: f, point: P, value: [\"velocity(Q, N).x\", 0, 0]}\n")),
              AllOf(HasSubstr("'Q' is not a point"), HasSubstr("velocity(P, F).x")));
  EXPECT_THAT(ErrorOf(Pendulum("  L: 0.6", "forces:\n  - {name: f, point: P, value: [\"velocity(P, N)\", 0, 0]}\n")),
              HasSubstr("component"));
  EXPECT_EQ(ErrorOf(Pendulum("  L: 0.6", "forces:\n  - {name: f, point: P, value: [\"-1 kg * velocity(P, A).y * angular_velocity(A, N).z\", 0, 0]}\n")),
            "no error");
}

TEST(ModelFileContractTest, CsvTablesEqualTheSameTablesInline) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("hybridtest-csv-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cp.csv") << "lambda, Cp\n0, 0\n1, 2  # peak\n3, 1\n";
  std::ofstream(dir / "ct.csv") << "x\\y, 0, 2\n0, 0, 20\n1, 1, 23\n3, 3, 29\n";
  std::ofstream(dir / "bad.csv") << "0, 0\n1, two\n";
  const std::string loads =
      "forces:\n  - {name: a, point: P, value: [\"f(x) + g(x, th)\", 0, 0]}\n";
  auto build = [&](const std::string& tables) {
    const std::string text = Pendulum("  L: 0.6", tables + loads);
    const std::filesystem::path file = dir / "m.yaml";
    std::ofstream(file) << text;
    const ModelFile f = LoadModelFile(file.string());
    return BuildModelFile(f, f.parameters);
  };
  const models::BuiltModel inline_tables = build(
      "tables:\n  f: {x: [0, 1, 3], y: [0, 2, 1]}\n"
      "  g: {x: [0, 1, 3], y: [0, 2], z: [[0, 20], [1, 23], [3, 29]]}\n");
  const models::BuiltModel csv_tables =
      build("tables:\n  f: {csv: cp.csv}\n  g: {csv_grid: ct.csv}\n");
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> d(-1, 4);
  for (int i = 0; i < 10; ++i) {
    Eigen::VectorXd x(4), a(4), b(4);
    x << d(rng), d(rng), d(rng), d(rng);
    multibody::Data<double> da(inline_tables.model), db(csv_tables.model);
    multibody::CalcStateDerivative<double>(inline_tables.model, da, 0.0, x, Eigen::VectorXd(), a);
    multibody::CalcStateDerivative<double>(csv_tables.model, db, 0.0, x, Eigen::VectorXd(), b);
    EXPECT_EQ(a, b);
  }
  auto error = [&](const std::string& tables) {
    try {
      build(tables);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error("tables:\n  f: {csv: nowhere.csv}\n  g: {csv_grid: ct.csv}\n"),
              AllOf(HasSubstr("tables.f.csv"), HasSubstr("cannot open"), HasSubstr("no such file")));
  EXPECT_THAT(error("tables:\n  f: {csv: bad.csv}\n  g: {csv_grid: ct.csv}\n"),
              AllOf(HasSubstr("bad.csv:2"), HasSubstr("not a row of numbers")));
  std::filesystem::remove_all(dir);
}

TEST(ModelFileContractTest, DeepExpressionsAreRefusedWithThePlace) {
  std::string s = Pendulum("  L: 0.6");
  s.replace(s.find("[L, 0, 0]"), 9, "[\"" + std::string(30000, '(') + "L" + std::string(30000, ')') + "\", 0, 0]");
  EXPECT_THAT(ErrorOf(s), AllOf(HasSubstr("m.yaml:11: points[1].position[0]"),
                                HasSubstr("nests deeper than")));
}

}  // namespace
}  // namespace hybridtest::modelfile
