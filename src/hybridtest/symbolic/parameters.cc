// Parameters as symbols, recovered by rebuilding the model. See parameters.h.
#include "hybridtest/symbolic/parameters.h"

#include <cmath>
#include <map>
#include <set>

#include "hybridtest/common/error.h"

namespace hybridtest::symbolic {

namespace {

using TermMap = std::map<GiNaC::ex, double, GiNaC::ex_is_less>;

std::vector<GiNaC::ex> TermsOf(const GiNaC::ex& e) {
  std::vector<GiNaC::ex> terms;
  if (GiNaC::is_a<GiNaC::add>(e)) {
    for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back(e.op(i));
  } else if (!e.is_zero()) {
    terms.push_back(e);
  }
  return terms;
}

// A term as (the product of its non-numeric factors, its numeric coefficient); false if the
// coefficient is not a real number.
bool Split(const GiNaC::ex& term, GiNaC::ex* rest, double* coefficient) {
  GiNaC::numeric c = 1;
  *rest = 1;
  if (GiNaC::is_a<GiNaC::numeric>(term)) {
    c = GiNaC::ex_to<GiNaC::numeric>(term);
  } else if (GiNaC::is_a<GiNaC::mul>(term)) {
    for (std::size_t i = 0; i < term.nops(); ++i) {
      if (GiNaC::is_a<GiNaC::numeric>(term.op(i))) {
        c *= GiNaC::ex_to<GiNaC::numeric>(term.op(i));
      } else {
        *rest *= term.op(i);
      }
    }
  } else {
    *rest = term;
  }
  if (!c.is_real()) return false;
  *coefficient = c.to_double();
  return true;
}

std::vector<TermMap> TermMaps(Equations& eq) {
  std::vector<TermMap> maps;
  for (GiNaC::ex* e : Outputs(eq)) {
    TermMap m;
    for (const GiNaC::ex& term : TermsOf(*e)) {
      GiNaC::ex rest;
      double c = 0.0;
      if (Split(term, &rest, &c)) m[rest] = c;
    }
    maps.push_back(std::move(m));
  }
  return maps;
}

// k as an exact rational with a denominator ≤ 1000 if it is one to 1e-12, else the float.
GiNaC::numeric Exact(double k) {
  for (long q = 1; q <= 1000; ++q) {
    const double p = std::round(k * static_cast<double>(q));
    if (std::abs(p) < 1e15 && std::abs(p / static_cast<double>(q) - k) <= 1e-12 * std::abs(k)) {
      return GiNaC::numeric(static_cast<long>(p), q);
    }
  }
  return GiNaC::numeric(k);
}

// The per-instance parameters "<prefix>.<name>" of a shared parameter <name> (a run config's
// blade1.m_b, blade2.m_b of the rotor's m_b).
std::vector<std::string> Instances(const models::ParameterSet& set, const std::string& name) {
  std::vector<std::string> out;
  for (const auto& p : set.all()) {
    const auto dot = p.name.rfind('.');
    if (dot != std::string::npos && p.name.compare(dot + 1, std::string::npos, name) == 0) {
      out.push_back(p.name);
    }
  }
  return out;
}

// Whether every instance of `shared` has its value (or inherits it: unset, NaN).
bool AllFollow(const models::ParameterSet& set, const std::string& shared) {
  const double value = set.Get(shared);
  for (const std::string& name : Instances(set, shared)) {
    const double v = set.Get(name);
    if (!std::isnan(v) && v != value) return false;
  }
  return true;
}

// Whether `name` is an instance ("blade1.m_b") of a shared parameter ("m_b") that every
// instance follows: it is then one symbol with it (issue 47 item 3: the prefix only where two
// instances differ).
bool FollowsShared(const models::ParameterSet& set, const std::string& name) {
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return false;
  const std::string shared = name.substr(dot + 1);
  return set.Has(shared) && AllFollow(set, shared);
}

// The parameters one symbol stands for: `name` and, if every instance follows it, its
// instances that carry a value.
std::vector<std::string> Group(const models::ParameterSet& set, const std::string& name) {
  std::vector<std::string> group = {name};
  if (name.find('.') != std::string::npos || !AllFollow(set, name)) return group;
  for (const std::string& instance : Instances(set, name)) {
    if (!std::isnan(set.Get(instance))) group.push_back(instance);
  }
  return group;
}

struct Candidate {
  std::string name;
  double value = 0.0;
  GiNaC::ex symbol;
  std::vector<TermMap> scaled;  // the terms with this parameter × kScale (empty: unusable)
  double check_factor = 1.0;    // its factor in the checking build
};

}  // namespace

SymbolizeReport SymbolizeParameters(
    Equations& eq, const models::ParameterSet& parameters,
    const std::function<multibody::Model(const models::ParameterSet&)>& build) {
  SymbolizeReport report;
  if (!eq.shared.definitions.empty()) return report;  // not expanded: no terms to match
  std::set<std::string> reserved = {"t"};
  for (const auto* list : {&eq.q, &eq.u, &eq.udot, &eq.r, &eq.z}) {
    for (const GiNaC::ex& s : *list) reserved.insert(GiNaC::ex_to<GiNaC::symbol>(s).get_name());
  }
  const std::size_t outputs = Outputs(eq).size();
  auto derive = [&](const models::ParameterSet& set, std::vector<TermMap>* maps) {
    try {
      Equations e = DeriveEquations(build(set));
      if (Outputs(e).size() != outputs) return false;
      // Every derivation makes its own symbols (GiNaC tells symbols apart by identity, not
      // name): write e in eq's, so that equal terms compare equal.
      GiNaC::exmap same = {{e.t, eq.t}};
      for (auto [from, to] : {std::pair{&e.q, &eq.q}, std::pair{&e.u, &eq.u},
                              std::pair{&e.udot, &eq.udot}, std::pair{&e.r, &eq.r},
                              std::pair{&e.z, &eq.z}}) {
        for (std::size_t i = 0; i < from->size(); ++i) same[(*from)[i]] = (*to)[i];
      }
      const auto& a_from = e.constrained.A;  // a constrained model's A_s_c
      for (std::size_t s = 0; s < a_from.size() && s < eq.constrained.A.size(); ++s) {
        for (std::size_t c = 0; c < a_from[s].size() && c < eq.constrained.A[s].size(); ++c) {
          same[a_from[s][c]] = eq.constrained.A[s][c];
        }
      }
      for (GiNaC::ex* x : Outputs(e)) *x = x->subs(same);
      *maps = TermMaps(e);
      return true;
    } catch (const Error&) {  // a scaled value the model refuses: that parameter stays a number
      return false;
    }
  };
  std::vector<Candidate> candidates;
  models::ParameterSet checking = parameters;
  for (const auto& p : parameters.all()) {
    if (p.value == 0.0 || !std::isfinite(p.value) || reserved.count(p.name) > 0) continue;
    if (FollowsShared(parameters, p.name)) continue;  // scaled with its shared value
    const std::vector<std::string> group = Group(parameters, p.name);
    Candidate c{p.name, p.value, GiNaC::realsymbol(p.name), {}, 1.0};
    models::ParameterSet scaled = parameters;
    for (const std::string& name : group) scaled.Set(name, p.value * kScale, "equations");
    if (!derive(scaled, &c.scaled)) continue;
    c.check_factor = 1.0 + 0.1 * static_cast<double>(candidates.size() % 7 + 1) +
                     0.0131 * static_cast<double>(candidates.size());
    for (const std::string& name : group) checking.Set(name, p.value * c.check_factor, "equations");
    candidates.push_back(std::move(c));
  }
  std::vector<TermMap> check;
  if (candidates.empty() || !derive(checking, &check)) return report;

  const std::vector<GiNaC::ex*> out = Outputs(eq);
  for (std::size_t o = 0; o < out.size(); ++o) {
    GiNaC::ex sum = 0;
    for (const GiNaC::ex& term : TermsOf(*out[o])) {
      GiNaC::ex rest;
      double c0 = 0.0;
      if (!Split(term, &rest, &c0) || c0 == 0.0) {
        sum += term;
        continue;
      }
      bool monomial = true, depends = false;
      std::vector<double> exponent(candidates.size(), 0.0);
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        const auto it = candidates[i].scaled[o].find(rest);
        const double ratio = it == candidates[i].scaled[o].end() ? 0.0 : it->second / c0;
        if (ratio != 1.0) depends = true;
        if (!(ratio > 0.0)) {
          monomial = false;
          continue;
        }
        const double e = std::log(ratio) / std::log(kScale);
        const double half = std::round(2.0 * e) / 2.0;
        const bool whole = half == std::round(half);
        if (std::abs(e - half) > 1e-7 || (!whole && candidates[i].value < 0.0)) monomial = false;
        exponent[i] = half;
      }
      if (!depends) {
        sum += term;
        continue;
      }
      double k = c0, expected = 1.0;
      GiNaC::ex product = 1;
      for (std::size_t i = 0; monomial && i < candidates.size(); ++i) {
        if (exponent[i] == 0.0) continue;
        k /= std::pow(candidates[i].value, exponent[i]);
        expected *= std::pow(candidates[i].check_factor, exponent[i]);
        product *= GiNaC::pow(candidates[i].symbol, GiNaC::numeric(static_cast<long>(2 * exponent[i]), 2));
      }
      const auto found = check[o].find(rest);
      if (!monomial || found == check[o].end() ||
          std::abs(found->second - c0 * expected) > 1e-9 * std::abs(c0 * expected)) {
        ++report.numeric_terms;
        sum += term;
        continue;
      }
      ++report.symbolic_terms;
      sum += Exact(k) * product * rest;
    }
    *out[o] = sum;
  }
  return report;
}

}  // namespace hybridtest::symbolic
