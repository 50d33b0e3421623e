// Parameters as symbols (issue 36 item 2): the rotor's M and f carry m_b, l_b, ζ_b, I_g where
// the paper's Eq. (19)-(20) have them, and for the rotor and the example model files the
// symbolic equations with the parameters' values substituted equal the numeric ones.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/symbolic/parameters.h"

namespace hybridtest::symbolic {
namespace {

std::map<std::string, GiNaC::ex> SymbolsOf(const GiNaC::ex& e) {
  std::map<std::string, GiNaC::ex> found;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (GiNaC::is_a<GiNaC::symbol>(*it)) found[GiNaC::ex_to<GiNaC::symbol>(*it).get_name()] = *it;
  }
  return found;
}

std::set<std::string> Names(const GiNaC::ex& e) {
  std::set<std::string> names;
  for (const auto& [name, symbol] : SymbolsOf(e)) names.insert(name);
  return names;
}

double Value(const GiNaC::ex& e, const GiNaC::exmap& at) {
  const GiNaC::ex v = GiNaC::evalf(e.subs(at));
  EXPECT_TRUE(GiNaC::is_a<GiNaC::numeric>(v)) << v;
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : 0.0;
}

// `symbolic` (after SymbolizeParameters) with the parameters' values equals `numeric` (the
// same model's DeriveEquations) in M, f and Fr at random states.
void ExpectSameValues(const Equations& symbolic, const Equations& numeric,
                      const models::ParameterSet& parameters) {
  const int n = static_cast<int>(numeric.q.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    GiNaC::exmap state, values;
    for (const auto* list : {&numeric.q, &numeric.u, &numeric.z}) {
      for (const GiNaC::ex& s : *list) state[s] = unit(rng);
    }
    for (const GiNaC::ex& s : numeric.r) state[s] = 1000.0 * unit(rng);
    state[numeric.t] = 2.0 + unit(rng);
    std::vector<GiNaC::ex> all;
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) all.push_back(symbolic.M[j][k]);
      all.push_back(symbolic.f[j]);
      all.push_back(symbolic.Fr[j]);
    }
    for (const GiNaC::ex& e : all) {
      for (const auto& [name, symbol] : SymbolsOf(e)) {
        if (parameters.Has(name)) values[symbol] = parameters.Get(name);
      }
    }
    std::size_t i = 0;
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const double want = Value(numeric.M[j][k], state);
        EXPECT_NEAR(Value(all[i++].subs(values), state), want, 1e-12 * std::max(1.0, std::abs(want)))
            << "M" << j << k;
      }
      for (const GiNaC::ex* e : {&numeric.f[j], &numeric.Fr[j]}) {
        const double want = Value(*e, state);
        EXPECT_NEAR(Value(all[i++].subs(values), state), want, 1e-10 * std::max(1.0, std::abs(want)))
            << "f/Fr " << j;
      }
    }
  }
}

TEST(SymbolizeParameters, RotorCarriesThePapersParameters) {
  const models::ParameterSet p = models::DefaultParameters("rotor", 3);
  const auto build = [](const models::ParameterSet& set) {
    return models::BuildModel("rotor", 3, set).model;
  };
  const Equations numeric = DeriveEquations(build(p));
  Equations eq = numeric;
  const SymbolizeReport report = SymbolizeParameters(eq, p, build);
  EXPECT_GT(report.symbolic_terms, 10);
  // Eq. (19): M_ii = m_b, M_i4 = m_b l_b; the hub entry has m_b q_i² terms.
  EXPECT_EQ(Names(eq.M[0][0]), (std::set<std::string>{"m_b"})) << eq.M[0][0];
  EXPECT_EQ(Names(eq.M[0][3]), (std::set<std::string>{"l_b", "m_b"})) << eq.M[0][3];
  EXPECT_TRUE(Names(eq.M[3][3]).count("m_b") > 0) << eq.M[3][3];
  // Eq. (20), a blade row: the damping ζ_b m_b u_1 (ζ_b as the model names it).
  const std::set<std::string> f0 = Names(eq.f[0]);
  EXPECT_TRUE(f0.count("m_b") > 0 && f0.count("r1") > 0) << eq.f[0];
  EXPECT_TRUE(f0.count("zeta_b") > 0 || f0.count("c_b") > 0) << eq.f[0];
  ExpectSameValues(eq, numeric, p);
}

// Issue 47 item 3: a run config resolves every blade's value (blade1.m_b = m_b); the printed
// symbol is still m_b, as for the model itself, and a blade's own symbol only where it differs.
TEST(SymbolizeParameters, ResolvedBladeValuesPrintAsTheSharedSymbol) {
  const auto build = [](const models::ParameterSet& set) {
    return models::BuildModel("rotor", 3, set).model;
  };
  const models::ParameterSet resolved =
      models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3)).parameters;
  ASSERT_TRUE(resolved.Has("blade1.m_b"));
  Equations eq = DeriveEquations(build(resolved));
  SymbolizeParameters(eq, resolved, build);
  EXPECT_EQ(Names(eq.M[0][0]), (std::set<std::string>{"m_b"})) << eq.M[0][0];
  EXPECT_EQ(Names(eq.M[2][3]), (std::set<std::string>{"l_b", "m_b"})) << eq.M[2][3];

  models::ParameterSet differs = resolved;
  differs.Set("blade2.m_b", 2.5, "test");
  Equations other = DeriveEquations(build(differs));
  SymbolizeParameters(other, differs, build);
  EXPECT_EQ(Names(other.M[1][1]), (std::set<std::string>{"blade2.m_b"})) << other.M[1][1];
  EXPECT_EQ(Names(other.M[0][0]), (std::set<std::string>{"blade1.m_b"})) << other.M[0][0];
}

TEST(SymbolizeParameters, ExampleModelFilesKeepTheirValues) {
  for (const char* stem : {"double_pendulum", "wind_turbine"}) {
    SCOPED_TRACE(stem);
    const auto file = modelfile::LoadModelFile(
        fmt::format("{}/examples/models/{}.yaml", HYBRIDTEST_SOURCE_DIR, stem));
    const auto build = [&file](const models::ParameterSet& set) {
      return modelfile::BuildModelFile(file, set).model;
    };
    const Equations numeric = DeriveEquations(build(file.parameters));
    Equations eq = numeric;
    const SymbolizeReport report = SymbolizeParameters(eq, file.parameters, build);
    EXPECT_GT(report.symbolic_terms, 0);
    ExpectSameValues(eq, numeric, file.parameters);
  }
}

// Issue 47: one rebuild per batch of up to twenty parameters (each scaled by its own prime), not
// one per parameter: the wind turbine's 17 parameters take one batch and the check (17 rebuilds
// and the check at first, then two batches of ten and the check), and its equations still carry
// the parameters.
TEST(SymbolizeParameters, OneRebuildPerBatchOfTwentyParameters) {
  const auto file = modelfile::LoadModelFile(
      fmt::format("{}/examples/models/wind_turbine.yaml", HYBRIDTEST_SOURCE_DIR));
  int builds = 0;
  const auto build = [&file, &builds](const models::ParameterSet& set) {
    ++builds;
    return modelfile::BuildModelFile(file, set).model;
  };
  ASSERT_EQ(file.parameters.all().size(), 17u);
  const Equations numeric = DeriveEquations(build(file.parameters));
  builds = 0;
  Equations eq = numeric;
  const SymbolizeReport report = SymbolizeParameters(eq, file.parameters, build);
  EXPECT_EQ(builds, 2);
  EXPECT_GT(report.symbolic_terms, 20);
  std::set<std::string> used;
  for (const auto& row : eq.M) {
    for (const GiNaC::ex& e : row) used.merge(Names(e));
  }
  for (const char* name : {"m_b", "L_b", "h_n", "H_t"}) EXPECT_TRUE(used.count(name) > 0) << name;
  ExpectSameValues(eq, numeric, file.parameters);
}

// 24 parameters take two batches. In the first, the product of the five parameters scaled by
// the batch's largest primes (53·59·61·67·71 ≈ 9e8) has a square beyond the continued
// fraction's bound: its exponents come from the ratio itself. In the second, 2 ζ √(k m) has half
// exponents (from the square). Every parameter stays a symbol and the values are the engine's.
TEST(SymbolizeParameters, TwoBatchesWithLargeProductsAndHalfExponents) {
  std::string text = "name: many\nparameters:\n";
  for (int i = 1; i <= 15; ++i) text += fmt::format("  p{:02}: {{value: 1.5, unit: '1'}}\n", i);
  for (int i = 1; i <= 5; ++i) text += fmt::format("  a{}: {{value: {}, unit: '1'}}\n", i, 1.0 + 0.25 * i);
  text +=
      "  k: {value: 800, unit: N/m}\n  m: {value: 2.0, unit: kg}\n  zeta: {value: 0.02, unit: '1'}\n"
      "  F: {value: 3.0, unit: N}\n"
      "coordinates:\n  - {name: x, unit: m}\nspeeds:\n  - {name: v, unit: m/s}\n"
      "points:\n  - {name: P, from: O, frame: N, position: [x, 0, 0]}\n"
      "particles:\n  - {name: mass, point: P, mass: m}\n"
      "forces:\n  - {name: spring, point: P, value: [-a1*a2*a3*a4*a5*k*x - 2*zeta*sqrt(k*m)*v + F, 0, 0]}\n";
  const auto file = modelfile::ParseModelFile(YamlInput::FromText(text, "many.yaml"));
  ASSERT_EQ(file.parameters.all().size(), 24u);
  int builds = 0;
  const auto build = [&file, &builds](const models::ParameterSet& set) {
    ++builds;
    return modelfile::BuildModelFile(file, set).model;
  };
  const Equations numeric = DeriveEquations(build(file.parameters));
  builds = 0;
  Equations eq = numeric;
  const SymbolizeReport report = SymbolizeParameters(eq, file.parameters, build);
  EXPECT_EQ(builds, 3);  // two batches and the check
  EXPECT_EQ(report.numeric_terms, 0);
  EXPECT_EQ(Names(eq.f[0]), (std::set<std::string>{"a1", "a2", "a3", "a4", "a5", "k", "x", "zeta",
                                                    "m", "v", "F"}))
      << eq.f[0];
  ExpectSameValues(eq, numeric, file.parameters);
}

// A batch whose scaled values the model refuses is rebuilt one parameter at a time: only the
// refused parameter (here l_b) stays a number.
TEST(SymbolizeParameters, ARefusedBatchFallsBackToOneParameterAtATime) {
  const models::ParameterSet p = models::DefaultParameters("rotor", 3);
  int builds = 0;
  const auto build = [&p, &builds](const models::ParameterSet& set) {
    ++builds;
    if (set.Get("l_b") != p.Get("l_b")) throw ModelError("test: l_b is fixed");
    return models::BuildModel("rotor", 3, set).model;
  };
  const Equations numeric = DeriveEquations(build(p));
  builds = 0;
  Equations eq = numeric;
  SymbolizeParameters(eq, p, build);
  EXPECT_EQ(Names(eq.M[0][0]), (std::set<std::string>{"m_b"})) << eq.M[0][0];
  EXPECT_EQ(Names(eq.M[0][3]), (std::set<std::string>{"m_b"})) << eq.M[0][3];  // m_b/2
  EXPECT_GT(builds, 3);  // the batch, then one parameter at a time, then the check
  ExpectSameValues(eq, numeric, p);
}

}  // namespace
}  // namespace hybridtest::symbolic
