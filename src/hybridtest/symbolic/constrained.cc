// The reduced equations of a constrained model as expressions. See constrained.h.
#include "hybridtest/symbolic/constrained.h"

#include <fmt/core.h>

#include <algorithm>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::symbolic {

namespace {

// The model's dependent speeds, else the engine's pivoted choice at the initial state.
void ChooseSpeeds(const multibody::Model& model, ConstrainedEquations& c) {
  multibody::Data<double> data(model);
  const Eigen::VectorXd x = model.initial_state();
  multibody::CalcKinematics<double>(model, data, 0.0, x);
  multibody::CalcConstraints<double>(model, data);
  if (!multibody::ChooseDependentSpeeds<double>(model, data)) {
    throw ModelError(fmt::format(
        "the constraints are redundant at the model's initial state (B has rank < {}, its "
        "number of rows), so the dependent speeds for the printed equations cannot be picked: "
        "name them (dependent_speeds:) or remove the redundant constraints",
        model.num_constraint_rows()));
  }
  c.dependent = data.dependent;
  c.independent = data.independent;
}

}  // namespace

ConstrainedEquations DeriveConstrained(const multibody::Model& model,
                                       multibody::Data<multibody::Symbolic>& data,
                                       const std::vector<GiNaC::ex>& u,
                                       const std::vector<std::vector<GiNaC::ex>>& M,
                                       const std::vector<GiNaC::ex>& f,
                                       const std::set<std::string>& reserved,
                                       const std::vector<std::vector<GiNaC::ex>>* same_A) {
  const int n = model.num_coordinates();
  const int m = model.num_constraint_rows();
  const int p = n - m;
  ConstrainedEquations c;
  ChooseSpeeds(model, c);
  multibody::CalcConstraints<multibody::Symbolic>(model, data);
  GiNaC::exmap at_rest;  // u = 0: B u + c becomes c (it is linear in u)
  for (const GiNaC::ex& s : u) at_rest[s] = 0;
  for (int s = 0; s < m; ++s) {
    c.rows.push_back(multibody::ConstraintRowName(model, s));
    std::vector<GiNaC::ex> dep, ind;
    for (int j : c.dependent) dep.push_back(data.constraint_B(s, j).ex());
    for (int j : c.independent) ind.push_back(data.constraint_B(s, j).ex());
    c.A_d.push_back(dep);
    c.A_i.push_back(ind);
    c.b.push_back(data.constraint_velocity(s).ex().subs(at_rest));
    c.bias.push_back(data.constraint_bias(s).ex());
    std::vector<GiNaC::ex> row;
    const auto si = static_cast<std::size_t>(s);
    for (int k = 0; k < p; ++k) {
      const auto ki = static_cast<std::size_t>(k);
      if (same_A != nullptr && si < same_A->size() && ki < (*same_A)[si].size()) {
        row.push_back((*same_A)[si][ki]);
        continue;
      }
      std::string name = fmt::format("A_{}_{}", s + 1, k + 1);
      while (reserved.count(name) > 0) name += "_";
      row.push_back(GiNaC::realsymbol(name));
    }
    c.A.push_back(row);
  }
  // [Cᵀ M; B] and [Cᵀ f; −bias], as CalcReducedEquations forms them.
  for (int k = 0; k < p; ++k) {
    const auto i = static_cast<std::size_t>(c.independent[static_cast<std::size_t>(k)]);
    std::vector<GiNaC::ex> row = M[i];
    GiNaC::ex rhs = f[i];
    for (int s = 0; s < m; ++s) {
      const auto d = static_cast<std::size_t>(c.dependent[static_cast<std::size_t>(s)]);
      const GiNaC::ex& a = c.A[static_cast<std::size_t>(s)][static_cast<std::size_t>(k)];
      for (int j = 0; j < n; ++j) row[static_cast<std::size_t>(j)] += a * M[d][static_cast<std::size_t>(j)];
      rhs += a * f[d];
    }
    c.M.push_back(row);
    c.f.push_back(rhs);
  }
  for (int s = 0; s < m; ++s) {
    std::vector<GiNaC::ex> row;
    for (int j = 0; j < n; ++j) row.push_back(data.constraint_B(s, j).ex());
    c.M.push_back(row);
    c.f.push_back(-c.bias[static_cast<std::size_t>(s)]);
  }
  return c;
}

std::vector<GiNaC::ex*> ConstrainedOutputs(ConstrainedEquations& c) {
  std::vector<GiNaC::ex*> out;
  auto add = [&](std::vector<GiNaC::ex>& v) {
    for (GiNaC::ex& e : v) out.push_back(&e);
  };
  for (auto& row : c.A_d) add(row);
  for (auto& row : c.A_i) add(row);
  add(c.b);
  add(c.bias);
  for (auto& row : c.M) add(row);
  add(c.f);
  return out;
}

}  // namespace hybridtest::symbolic
