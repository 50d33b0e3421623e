// The engine's equations as expressions. See equations.h.
#include "hybridtest/symbolic/equations.h"

#include <fmt/core.h>

#include <set>

#include "hybridtest/common/error.h"

#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/shared.h"
#include "hybridtest/symbolic/simplify.h"

namespace hybridtest::symbolic {

using multibody::Data;
using multibody::LoadArgs;
using multibody::LoadSpec;
using multibody::Symbolic;
using multibody::Vector3;
using multibody::VectorX;

namespace {

// New symbols named `names`, or `same`'s symbols when it has one per name (a derivation like
// another one, DeriveEquations).
std::vector<GiNaC::ex> Variables(const std::vector<std::string>& names, VectorX<Symbolic>& out,
                                 const std::vector<GiNaC::ex>* same) {
  std::vector<GiNaC::ex> symbols;
  out.resize(static_cast<Eigen::Index>(names.size()));
  const bool reuse = same != nullptr && same->size() == names.size();
  for (std::size_t k = 0; k < names.size(); ++k) {
    out(static_cast<Eigen::Index>(k)) =
        reuse ? Symbolic((*same)[k]) : Symbolic::Variable(names[k]);
    symbols.push_back(out(static_cast<Eigen::Index>(k)).ex());
  }
  return symbols;
}

GiNaC::ex Dot(const Symbolic* a, const Symbolic* b) {
  return a[0].ex() * b[0].ex() + a[1].ex() * b[1].ex() + a[2].ex() * b[2].ex();
}

// The partials of one point or frame (3 × n), as the engine computed them.
std::vector<std::vector<GiNaC::ex>> Columns(const multibody::Matrix3X<Symbolic>& V) {
  std::vector<std::vector<GiNaC::ex>> columns;
  for (Eigen::Index j = 0; j < V.cols(); ++j) {
    std::vector<GiNaC::ex> col;
    for (int c = 0; c < 3; ++c) col.push_back(V(c, j).ex());
    columns.push_back(col);
  }
  return columns;
}

// Drops the points or frames whose partials are all zero.
void DropZero(std::vector<NamedPartials>& partials) {
  std::erase_if(partials, [](const NamedPartials& p) {
    for (const auto& column : p.columns) {
      for (const GiNaC::ex& e : column) {
        if (!e.is_zero()) return false;
      }
    }
    return true;
  });
}

// The engine on Symbolic at symbolic (t, x, r): fills `data` and eq's symbols (t, q, u, z, r,
// udot), named as the model names its quantities, or `like`'s symbols if not null.
void RunEngine(const multibody::Model& model, Data<Symbolic>& data, Equations& eq,
               const Equations* like) {
  const int n = model.num_coordinates();
  std::vector<std::string> names;
  for (const auto& c : model.coordinates()) names.push_back(c.name);
  for (const auto& s : model.speeds()) names.push_back(s.name);
  for (const auto& z : model.extra_states()) names.push_back(z.info.name);
  std::vector<GiNaC::ex> like_x;
  if (like != nullptr) {
    like_x = like->q;
    like_x.insert(like_x.end(), like->u.begin(), like->u.end());
    like_x.insert(like_x.end(), like->z.begin(), like->z.end());
  }
  VectorX<Symbolic> x;
  const std::vector<GiNaC::ex> xs = Variables(names, x, like != nullptr ? &like_x : nullptr);
  eq.q.assign(xs.begin(), xs.begin() + n);
  eq.u.assign(xs.begin() + n, xs.begin() + 2 * n);
  eq.z.assign(xs.begin() + 2 * n, xs.end());
  names.clear();
  for (const auto& s : model.slots()) names.push_back(s.info.name);
  VectorX<Symbolic> r;
  eq.r = Variables(names, r, like != nullptr ? &like->r : nullptr);
  const Symbolic t = like != nullptr ? Symbolic(like->t) : Symbolic::Variable("t");
  eq.t = t.ex();
  names.clear();
  for (const auto& s : model.speeds()) names.push_back(s.name + "_dot");
  VectorX<Symbolic> udot;
  eq.udot = Variables(names, udot, like != nullptr ? &like->udot : nullptr);

  multibody::CalcKinematics<Symbolic>(model, data, t, x);
  multibody::CalcMassMatrixPairwise<Symbolic>(model, data);
  multibody::CalcForcing<Symbolic>(model, data, r);
}

LoadArgs<Symbolic> Arguments(const Data<Symbolic>& data, bool with_r) {
  const auto n = static_cast<std::size_t>(data.n);
  return LoadArgs<Symbolic>{
      data.t, std::span<const Symbolic>(data.q.data(), n),
      std::span<const Symbolic>(data.u.data(), n),
      with_r ? std::span<const Symbolic>(data.r.data(), data.r.size())
             : std::span<const Symbolic>(),
      std::span<const Symbolic>(data.time_values.data(), data.time_values.size()),
      std::span<const Symbolic>(data.z.data(), data.z.size())};
}

std::vector<GiNaC::ex> ExtraStateRates(const multibody::Model& model, const Data<Symbolic>& data) {
  std::vector<GiNaC::ex> zdot;
  const LoadArgs<Symbolic> zargs = Arguments(data, false);
  for (const auto& state : model.extra_states()) {
    zdot.push_back(state.rate.get<Symbolic>()(zargs).ex());
  }
  return zdot;
}

}  // namespace

std::vector<GiNaC::ex*> Outputs(Equations& eq) {
  std::vector<GiNaC::ex*> out;
  auto add = [&](std::vector<GiNaC::ex>& v) {
    for (GiNaC::ex& e : v) out.push_back(&e);
  };
  for (auto& row : eq.M) add(row);
  add(eq.f);
  add(eq.Fr);
  add(eq.Fr_star);
  add(eq.qdot);
  add(eq.zdot);
  for (auto* partials : {&eq.point_partials, &eq.frame_partials}) {
    for (auto& p : *partials) {
      for (auto& column : p.columns) add(column);
    }
  }
  for (GiNaC::ex* e : ConstrainedOutputs(eq.constrained)) out.push_back(e);
  return out;
}

RhsExpressions DeriveRhs(const multibody::Model& model) {
  const int n = model.num_coordinates();
  Data<Symbolic> data(model);
  Equations symbols;
  RunEngine(model, data, symbols, nullptr);
  RhsExpressions rhs;
  rhs.t = symbols.t;
  rhs.x = symbols.q;
  rhs.x.insert(rhs.x.end(), symbols.u.begin(), symbols.u.end());
  rhs.x.insert(rhs.x.end(), symbols.z.begin(), symbols.z.end());
  rhs.r = symbols.r;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) rhs.M.push_back(data.M(j, k).ex());
    rhs.g.push_back(data.g(k).ex());
    rhs.qdot.push_back(data.qdot(k).ex());
  }
  rhs.zdot = ExtraStateRates(model, data);
  if (model.has_constraints()) {
    // After the forcing, as the engine's constrained step computes them.
    multibody::CalcConstraints<Symbolic>(model, data);
    const int m = model.num_constraint_rows();
    for (int j = 0; j < n; ++j) {
      for (int s = 0; s < m; ++s) rhs.B.push_back(data.constraint_B(s, j).ex());
    }
    for (int s = 0; s < m; ++s) {
      rhs.constraint_velocity.push_back(data.constraint_velocity(s).ex());
      rhs.constraint_position.push_back(data.constraint_position(s).ex());
      rhs.constraint_bias.push_back(data.constraint_bias(s).ex());
    }
  }
  return rhs;
}

Equations DeriveEquations(const multibody::Model& model, const Equations* like) {
  const int n = model.num_coordinates();
  Equations eq;
  Data<Symbolic> data(model);
  RunEngine(model, data, eq, like);

  // Fr: the applied loads alone, projected as CalcForcing projects them.
  std::vector<Vector3<Symbolic>> force(model.points().size(), Vector3<Symbolic>::Zero());
  std::vector<Vector3<Symbolic>> torque(model.frames().size(), Vector3<Symbolic>::Zero());
  const LoadArgs<Symbolic> args = Arguments(data, true);
  for (const LoadSpec& load : model.loads()) {
    const Vector3<Symbolic> value = load.function.get<Symbolic>()(args);
    const Vector3<Symbolic> in_N =
        load.expressed_in == 0 ? value : Vector3<Symbolic>(data.R_NF[load.expressed_in] * value);
    auto& sum = (load.kind == LoadSpec::Kind::kForce ? force : torque)[load.target];
    sum = Vector3<Symbolic>(sum + in_N);
  }
  eq.Fr.assign(n, 0);
  for (int j = 0; j < n; ++j) {
    GiNaC::ex s = 0;
    for (std::size_t p = 0; p < force.size(); ++p) {
      s += Dot(data.v_partial[p].data() + 3 * j, force[p].data());
    }
    for (std::size_t f = 0; f < torque.size(); ++f) {
      s += Dot(data.w_partial[f].data() + 3 * j, torque[f].data());
    }
    eq.Fr[j] = s;
  }
  eq.M.assign(n, std::vector<GiNaC::ex>(n, 0));
  eq.f.assign(n, 0);
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < n; ++k) eq.M[j][k] = data.M(j, k).ex();
    eq.f[j] = data.g(j).ex();
  }
  for (int k = 0; k < n; ++k) eq.qdot.push_back(data.qdot(k).ex());
  eq.zdot = ExtraStateRates(model, data);
  std::set<std::string> reserved = {"t"};
  for (const auto& list : {eq.q, eq.u, eq.udot, eq.r, eq.z}) {
    for (const GiNaC::ex& sym : list) reserved.insert(GiNaC::ex_to<GiNaC::symbol>(sym).get_name());
  }
  if (model.has_constraints()) {
    eq.constrained = DeriveConstrained(model, data, eq.u, eq.M, eq.f, reserved,
                                       like != nullptr ? &like->constrained.A : nullptr);
    for (const auto& row : eq.constrained.A) {
      for (const GiNaC::ex& a : row) reserved.insert(GiNaC::ex_to<GiNaC::symbol>(a).get_name());
    }
  }
  // Partial velocities and partial angular velocities (frame 0 and point 0 are N and O).
  for (std::size_t f = 1; f < model.frames().size(); ++f) {
    eq.frame_partials.push_back({model.frames()[f].name, Columns(data.w_partial[f])});
  }
  for (std::size_t p = 1; p < model.points().size(); ++p) {
    eq.point_partials.push_back({model.points()[p].name, Columns(data.v_partial[p])});
  }
  eq.Fr_star.assign(n, 0);
  const auto inertia_forces = [&] {
    for (int j = 0; j < n; ++j) {
      GiNaC::ex s = eq.f[j] - eq.Fr[j];
      for (int k = 0; k < n; ++k) s -= eq.M[j][k] * eq.udot[k];
      eq.Fr_star[j] = s;
    }
  };

  std::vector<GiNaC::ex> all;
  for (GiNaC::ex* e : Outputs(eq)) all.push_back(*e);
  if (ExpandedTerms(all) <= kExpandLimit) {
    Simplifier simplify;  // one for all outputs: they share subexpressions
    for (GiNaC::ex* e : Outputs(eq)) *e = simplify(*e);
    inertia_forces();
    for (GiNaC::ex& e : eq.Fr_star) e = simplify(e);
  } else {
    // Too large to expand: the engine's expressions, with their common subexpressions named.
    inertia_forces();
    eq.shared = ShareSubexpressions(Outputs(eq), "cse", reserved);
  }
  DropZero(eq.frame_partials);
  DropZero(eq.point_partials);
  return eq;
}

}  // namespace hybridtest::symbolic
