// Parameters as symbols, recovered by rebuilding the model. See parameters.h.
#include "hybridtest/symbolic/parameters.h"

#include <algorithm>
#include <array>
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
  std::vector<std::string> group;  // the parameter names this symbol stands for
  bool angle = false;              // unit rad: derived alone, may stay inside a function
  long factor = 1;                 // its prime in the scaled build of its batch
  std::size_t batch = 0;           // its scaled build (index into the batches' term maps)
  double check_factor = 1.0;       // its factor in the checking build
};

// How often `prime` divides *n (dividing it out).
int Valuation(long* n, long prime) {
  int v = 0;
  while (*n % prime == 0) *n /= prime, ++v;
  return v;
}

// Whether num/den = Π p_i^(power · e_i) over the batch's primes (power 1 or 2); e gets the e_i.
bool Factor(long num, long den, const std::vector<Candidate*>& batch, int power,
            std::vector<double>* e) {
  e->clear();
  for (const Candidate* c : batch) {
    const int times = Valuation(&num, c->factor) - Valuation(&den, c->factor);
    if (std::abs(times) > 6 * power) return false;
    e->push_back(static_cast<double>(times) / power);
  }
  return num == 1 && den == 1;
}

// The exponents e_i of a batch's parameters in a term whose coefficient the batch's build
// (parameter i × its prime p_i) scaled by `ratio` = Π p_i^e_i: ratio² (e_i whole or half) or,
// when that is too large a fraction, `ratio` (e_i whole) is a fraction of products of the
// primes, found among the convergents of its continued fraction within 1e-13 (the
// coefficients are the model's doubles, exact to rounding). False if the ratio is no such
// product (a coefficient that is a sum of parameter products).
bool BatchExponents(double ratio, const std::vector<Candidate*>& batch, std::vector<double>* out) {
  if (!(ratio > 0.0)) return false;
  constexpr double kLimit = 1e12;
  std::vector<double> e;
  for (const int power : {2, 1}) {
    const double x = power == 1 ? ratio : ratio * ratio;
    double h0 = 0.0, h1 = 1.0, k0 = 1.0, k1 = 0.0, y = x;
    for (int step = 0; step < 64; ++step) {
      const double a = std::floor(y);
      const double h2 = a * h1 + h0, k2 = a * k1 + k0;
      if (h2 > kLimit || k2 > kLimit) break;
      h0 = h1, h1 = h2, k0 = k1, k1 = k2;
      if (std::abs(h1 / k1 - x) <= 1e-13 * x &&
          Factor(static_cast<long>(h1), static_cast<long>(k1), batch, power, &e)) {
        out->insert(out->end(), e.begin(), e.end());
        return true;
      }
      const double rest = y - a;
      if (rest <= 0.0) break;
      y = 1.0 / rest;
    }
  }
  return false;
}

// Distinct primes, one per parameter of a batch: one derivation scales all of them.
constexpr std::array<long, 20> kPrimes = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29,
                                          31, 37, 41, 43, 47, 53, 59, 61, 67, 71};

}  // namespace

bool IsFollowingInstance(const models::ParameterSet& parameters, const std::string& name) {
  return FollowsShared(parameters, name);
}

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
      // eq's symbols, so that equal terms compare equal.
      Equations e = DeriveEquations(build(set), &eq);
      if (Outputs(e).size() != outputs) return false;
      *maps = TermMaps(e);
      return true;
    } catch (const Error&) {  // a scaled value the model refuses: that parameter stays a number
      return false;
    }
  };
  std::vector<Candidate> all;
  for (const auto& p : parameters.all()) {
    if (p.value == 0.0 || !std::isfinite(p.value) || reserved.count(p.name) > 0) continue;
    if (FollowsShared(parameters, p.name)) continue;  // scaled with its shared value
    all.push_back({p.name, p.value, GiNaC::realsymbol(p.name), Group(parameters, p.name),
                   p.unit == "rad"});
  }
  // Angles last, one per batch: an angle inside a function (the rotor's blade azimuth in
  // sin(q4 + ψ)) scales no term by a product of primes, which would spoil the batch of every
  // other parameter of such a term.
  std::stable_partition(all.begin(), all.end(), [](const Candidate& c) { return !c.angle; });
  // One derivation per batch of up to kPrimes.size() parameters, each scaled by its prime; a
  // batch the model refuses is derived again one parameter at a time, and a parameter whose
  // scaled value the model refuses stays a number.
  std::vector<std::vector<TermMap>> scaled;  // per batch
  std::vector<Candidate> candidates;
  const auto derive_batch = [&](std::vector<Candidate> batch) {
    models::ParameterSet set = parameters;
    for (std::size_t i = 0; i < batch.size(); ++i) {
      batch[i].factor = kPrimes[i];
      batch[i].batch = scaled.size();
      for (const std::string& name : batch[i].group) {
        set.Set(name, batch[i].value * static_cast<double>(kPrimes[i]), "equations");
      }
    }
    std::vector<TermMap> maps;
    if (!derive(set, &maps)) return false;
    scaled.push_back(std::move(maps));
    candidates.insert(candidates.end(), batch.begin(), batch.end());
    return true;
  };
  const auto angles = static_cast<std::size_t>(
      std::count_if(all.begin(), all.end(), [](const Candidate& c) { return c.angle; }));
  for (std::size_t first = 0; first < all.size();) {
    const std::size_t others = all.size() - angles;
    const std::size_t last =
        first >= others ? first + 1 : std::min(others, first + kPrimes.size());
    std::vector<Candidate> batch(all.begin() + static_cast<std::ptrdiff_t>(first),
                                 all.begin() + static_cast<std::ptrdiff_t>(last));
    first = last;
    if (derive_batch(batch) || batch.size() == 1) continue;
    for (const Candidate& c : batch) derive_batch({c});
  }
  std::vector<std::vector<Candidate*>> batches(scaled.size());
  for (Candidate& c : candidates) batches[c.batch].push_back(&c);
  const std::vector<GiNaC::ex*> out = Outputs(eq);
  // The exponents of a term's coefficient c0 (its rest: the factor of q, u, t, r, z) in the
  // candidates' order; an angle whose own build scales the term by no product of primes
  // stays inside it (exponent 0, *inside set); false if another parameter does so.
  const auto exponents = [&](std::size_t o, const GiNaC::ex& rest, double c0,
                             std::vector<double>* exponent, std::vector<bool>* inside,
                             bool* depends) {
    bool monomial = true;
    for (std::size_t b = 0; b < batches.size(); ++b) {
      const auto it = scaled[b][o].find(rest);
      const double ratio = it == scaled[b][o].end() ? 0.0 : it->second / c0;
      if (ratio != 1.0) *depends = true;
      const std::size_t before = exponent->size();
      if (!BatchExponents(ratio, batches[b], exponent)) {
        if (batches[b].size() == 1 && batches[b][0]->angle) {
          (*inside)[before] = true;
        } else {
          monomial = false;
        }
      }
      exponent->resize(before + batches[b].size());
    }
    return monomial;
  };
  // An angle that stays inside some term is not scaled in the checking build.
  std::vector<bool> kept_inside(candidates.size(), false);
  for (std::size_t o = 0; o < out.size(); ++o) {
    for (const GiNaC::ex& term : TermsOf(*out[o])) {
      GiNaC::ex rest;
      double c0 = 0.0;
      if (!Split(term, &rest, &c0) || c0 == 0.0) continue;
      std::vector<double> exponent;
      std::vector<bool> inside(candidates.size(), false);
      bool depends = false;
      exponents(o, rest, c0, &exponent, &inside, &depends);
      for (std::size_t i = 0; i < inside.size(); ++i) {
        if (inside[i]) kept_inside[i] = true;
      }
    }
  }
  models::ParameterSet checking = parameters;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    Candidate& c = candidates[i];
    c.check_factor = kept_inside[i] ? 1.0
                                    : 1.0 + 0.1 * static_cast<double>(i % 7 + 1) +
                                          0.0131 * static_cast<double>(i);
    for (const std::string& name : c.group) checking.Set(name, c.value * c.check_factor, "equations");
  }
  std::vector<TermMap> check;
  if (candidates.empty() || !derive(checking, &check)) return report;

  for (std::size_t o = 0; o < out.size(); ++o) {
    GiNaC::ex sum = 0;
    for (const GiNaC::ex& term : TermsOf(*out[o])) {
      GiNaC::ex rest;
      double c0 = 0.0;
      if (!Split(term, &rest, &c0) || c0 == 0.0) {
        sum += term;
        continue;
      }
      bool depends = false;
      std::vector<double> exponent;  // in the order of `candidates` (batch by batch)
      std::vector<bool> inside(candidates.size(), false);
      bool monomial = exponents(o, rest, c0, &exponent, &inside, &depends);
      for (std::size_t i = 0; i < inside.size(); ++i) {
        if (inside[i] && !kept_inside[i]) monomial = false;  // cannot happen; be safe
      }
      if (!depends) {
        sum += term;
        continue;
      }
      double k = c0, expected = 1.0;
      GiNaC::ex product = 1;
      for (std::size_t i = 0; monomial && i < candidates.size(); ++i) {
        if (exponent[i] == 0.0) continue;
        if (exponent[i] != std::round(exponent[i]) && candidates[i].value < 0.0) monomial = false;
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
