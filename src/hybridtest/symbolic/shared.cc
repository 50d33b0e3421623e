// Named common subexpressions in a fixed order. See shared.h.
#include "hybridtest/symbolic/shared.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "hybridtest/symbolic/simplify.h"

namespace hybridtest::symbolic {

namespace {

using ExMap = std::map<GiNaC::ex, std::size_t, GiNaC::ex_is_less>;

bool IsLeaf(const GiNaC::ex& e) {
  return GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e) ||
         GiNaC::is_a<GiNaC::constant>(e);
}

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

std::uint64_t Fnv(std::uint64_t h, const std::string& text) {
  for (unsigned char c : text) h = (h ^ c) * kFnvPrime;
  return h;
}
std::uint64_t Mix(std::uint64_t h, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) h = (h ^ ((v >> (8 * i)) & 0xffU)) * kFnvPrime;
  return h;
}

// e = sign · canon(e), with `hash` the hash of canon(e): e and −e hash alike.
struct Signed {
  std::uint64_t hash = kFnvOffset;
  int sign = 1;
};

std::uint64_t Combine(const std::string& kind, const std::vector<std::uint64_t>& parts) {
  std::uint64_t h = Fnv(kFnvOffset, kind);
  for (std::uint64_t v : parts) h = Mix(h, v);
  return h;
}
std::uint64_t WithSign(const Signed& s) { return Mix(s.hash, s.sign > 0 ? 1U : 2U); }

// GiNaC's mul::eval takes the unit (sign) out of a sum that is a factor of a product, by the
// sign of the sum's first term in its address-dependent order: one process writes y·(x − a),
// another −y·(a − x). The canonical sign of a sum is the one of {s, −s} whose sorted term
// hashes hash lower; a product's sign is the product of its factors' (a power's: its base's if
// the exponent is odd). Numbers by value, symbols by name: nothing depends on addresses.
class Hasher {
 public:
  Signed operator()(const GiNaC::ex& e) {
    const auto it = memo_.find(e);
    if (it != memo_.end()) return it->second;
    Signed out;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      out.hash = Fnv(Fnv(kFnvOffset, "s:"), GiNaC::ex_to<GiNaC::symbol>(e).get_name());
    } else if (GiNaC::is_a<GiNaC::numeric>(e)) {
      const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
      const bool negative = n.is_real() && n.is_negative();
      out = {Fnv(Fnv(kFnvOffset, "n:"), Text(negative ? GiNaC::ex(-n) : e)), negative ? -1 : 1};
    } else if (GiNaC::is_a<GiNaC::constant>(e)) {
      out.hash = Fnv(Fnv(kFnvOffset, "c:"), Text(e));
    } else if (GiNaC::is_a<GiNaC::add>(e)) {
      std::vector<std::uint64_t> plus, minus;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        Signed t = (*this)(e.op(i));
        plus.push_back(WithSign(t));
        t.sign = -t.sign;
        minus.push_back(WithSign(t));
      }
      std::sort(plus.begin(), plus.end());
      std::sort(minus.begin(), minus.end());
      const std::uint64_t hp = Combine("add", plus), hm = Combine("add", minus);
      out = hp <= hm ? Signed{hp, 1} : Signed{hm, -1};
    } else if (GiNaC::is_a<GiNaC::mul>(e)) {
      std::vector<std::uint64_t> factors;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const GiNaC::ex& f = e.op(i);
        const Signed t = (*this)(f);
        out.sign *= t.sign;
        // A coefficient ±1 is no factor: y·(x − a) and −1·y·(a − x) are the same product.
        if (GiNaC::is_a<GiNaC::numeric>(f) && abs(GiNaC::ex_to<GiNaC::numeric>(f)).is_equal(1)) continue;
        factors.push_back(t.hash);
      }
      // −x is the product (−1)·x: with the coefficient dropped, its one factor's hash, so that
      // x and −x hash alike (and so do a − x² and x² − a, whose terms GiNaC holds as x² and
      // the product −1·x²; otherwise which of the two a process holds changes every hash above).
      std::sort(factors.begin(), factors.end());
      out.hash = factors.size() == 1 ? factors.front() : Combine("mul", factors);
    } else if (GiNaC::is_a<GiNaC::power>(e)) {
      const Signed base = (*this)(e.op(0));
      const GiNaC::ex& k = e.op(1);
      if (GiNaC::is_a<GiNaC::numeric>(k) && GiNaC::ex_to<GiNaC::numeric>(k).is_integer()) {
        const bool odd = GiNaC::ex_to<GiNaC::numeric>(k).is_odd();
        out = {Combine("pow", {base.hash, WithSign((*this)(k))}), odd ? base.sign : 1};
      } else {
        out.hash = Combine("pow", {WithSign(base), WithSign((*this)(k))});
      }
    } else {
      std::string kind = GiNaC::ex_to<GiNaC::basic>(e).class_name();
      if (GiNaC::is_a<GiNaC::function>(e)) {
        kind += ':';  // (not ":" + name: GCC 12 warns -Wrestrict on it, wrongly)
        kind += GiNaC::ex_to<GiNaC::function>(e).get_name();
      }
      std::vector<std::uint64_t> ops;
      for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back(WithSign((*this)(e.op(i))));
      out.hash = Combine(kind, ops);
    }
    memo_.emplace(e, out);
    return out;
  }

  // The one of {e, −e} whose sign is +1: the key under which e and −e are one subexpression.
  GiNaC::ex Canonical(const GiNaC::ex& e) {
    if ((*this)(e).sign > 0) return e;
    const auto it = negated_.find(e);
    if (it != negated_.end()) return it->second;
    const GiNaC::ex minus = -e;
    negated_.emplace(e, minus);
    return minus;
  }

 private:
  static std::string Text(const GiNaC::ex& e) {
    std::ostringstream os;
    os.precision(17);
    os << e;
    return os.str();
  }
  std::map<GiNaC::ex, Signed, GiNaC::ex_is_less> memo_;
  std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less> negated_;
};

// The operands of e, in canonical order: by their hashes without their signs (a product's
// factors are y and (x − a) in one process, y, (a − x) and −1 in another).
std::vector<GiNaC::ex> SortedOperands(const GiNaC::ex& e, Hasher& hash) {
  std::vector<std::pair<Signed, GiNaC::ex>> ops;
  for (std::size_t i = 0; i < e.nops(); ++i) ops.emplace_back(hash(e.op(i)), e.op(i));
  std::stable_sort(ops.begin(), ops.end(), [](const auto& a, const auto& b) {
    return a.first.hash != b.first.hash ? a.first.hash < b.first.hash : a.first.sign < b.first.sign;
  });
  std::vector<GiNaC::ex> out;
  for (auto& [h, op] : ops) out.push_back(op);
  return out;
}

// A sum, product or power of two leaves: printed inline, never named.
bool IsTrivial(const GiNaC::ex& e) {
  if (IsLeaf(e)) return true;
  if (GiNaC::is_a<GiNaC::function>(e) || e.nops() > 2) return false;
  for (std::size_t i = 0; i < e.nops(); ++i) {
    if (!IsLeaf(e.op(i))) return false;
  }
  return true;
}

class Sharer {
 public:
  // Counts the uses of every subexpression (each parent occurrence once).
  // e and −e count as one (their canonical form, Hasher::Canonical).
  void Count(const GiNaC::ex& e) {
    if (IsLeaf(e)) return;
    const GiNaC::ex key = hash_.Canonical(e);
    const auto [it, fresh] = uses_.try_emplace(key, 0);
    ++it->second;
    if (!fresh) return;
    for (std::size_t i = 0; i < key.nops(); ++i) Count(key.op(i));
  }

  // Numbers the shared subexpressions depth-first, operands in canonical order.
  void Number(const GiNaC::ex& e) {
    if (IsLeaf(e)) return;
    const GiNaC::ex key = hash_.Canonical(e);
    if (!visited_.emplace(key, 0).second) return;
    for (const GiNaC::ex& op : SortedOperands(key, hash_)) Number(op);
    if (uses_[key] >= 2 && !IsTrivial(key)) {
      index_.emplace(key, order_.size());
      order_.push_back(key);
    }
  }

  // e with its operands rebuilt (shared ones as their symbols), e itself not replaced.
  GiNaC::ex RebuildBody(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return ExactDyadic(GiNaC::ex_to<GiNaC::numeric>(e));
    if (IsLeaf(e)) return e;
    const auto it = rebuilt_.find(e);
    if (it != rebuilt_.end()) return it->second;
    struct Operand : GiNaC::map_function {
      Sharer* self;
      explicit Operand(Sharer* s) : self(s) {}
      GiNaC::ex operator()(const GiNaC::ex& op) override { return self->Use(op); }
    } operand(this);
    const GiNaC::ex body = e.map(operand);
    rebuilt_.emplace(e, body);
    return body;
  }

  // e as it appears where it is used: its symbol if shared.
  GiNaC::ex Use(const GiNaC::ex& e) {
    if (IsLeaf(e)) return RebuildBody(e);
    const GiNaC::ex key = hash_.Canonical(e);
    const int sign = hash_(e).sign;
    const auto it = index_.find(key);
    const GiNaC::ex body = it != index_.end() ? GiNaC::ex(symbols_[it->second]) : RebuildBody(key);
    return sign > 0 ? body : -body;
  }

  SharedSubexpressions Finish(const std::vector<GiNaC::ex*>& outputs, const std::string& prefix,
                              const std::set<std::string>& reserved) {
    for (std::size_t k = 0; k < order_.size(); ++k) {
      std::string name = fmt::format("{}{}", prefix, k + 1);
      while (reserved.count(name) > 0) name += "_";
      symbols_.push_back(GiNaC::realsymbol(name));
    }
    SharedSubexpressions shared;
    for (std::size_t k = 0; k < order_.size(); ++k) {
      shared.definitions.emplace_back(symbols_[k], RebuildBody(order_[k]));
    }
    for (GiNaC::ex* e : outputs) *e = Use(*e);
    return shared;
  }

 private:
  Hasher hash_;
  ExMap uses_, visited_, index_;
  std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less> rebuilt_;
  std::vector<GiNaC::ex> order_;
  std::vector<GiNaC::ex> symbols_;
};

}  // namespace

double ExpandedTerms(const std::vector<GiNaC::ex>& expressions) {
  constexpr double kCap = 1e15;
  std::map<GiNaC::ex, double, GiNaC::ex_is_less> memo;
  const auto terms = [&](const auto& self, const GiNaC::ex& e) -> double {
    if (IsLeaf(e) || GiNaC::is_a<GiNaC::function>(e)) return 1.0;
    const auto it = memo.find(e);
    if (it != memo.end()) return it->second;
    double n = 1.0;
    if (GiNaC::is_a<GiNaC::add>(e)) {
      n = 0.0;
      for (std::size_t i = 0; i < e.nops(); ++i) n += self(self, e.op(i));
    } else if (GiNaC::is_a<GiNaC::mul>(e)) {
      for (std::size_t i = 0; i < e.nops(); ++i) n *= self(self, e.op(i));
    } else if (GiNaC::is_a<GiNaC::power>(e)) {
      const double base = self(self, e.op(0));
      const GiNaC::ex& k = e.op(1);
      n = base;
      if (GiNaC::is_a<GiNaC::numeric>(k) && GiNaC::ex_to<GiNaC::numeric>(k).is_pos_integer()) {
        n = std::pow(base, std::min(GiNaC::ex_to<GiNaC::numeric>(k).to_double(), 60.0));
      }
    }
    n = std::min(n, kCap);
    memo.emplace(e, n);
    return n;
  };
  double total = 0.0;
  for (const GiNaC::ex& e : expressions) total = std::min(total + terms(terms, e), kCap);
  return total;
}

std::uint64_t CanonicalHash(const GiNaC::ex& e) {
  Hasher hash;
  return WithSign(hash(e));
}

SharedSubexpressions ShareSubexpressions(const std::vector<GiNaC::ex*>& outputs,
                                         const std::string& prefix,
                                         const std::set<std::string>& reserved) {
  Sharer sharer;
  for (const GiNaC::ex* e : outputs) sharer.Count(*e);
  for (const GiNaC::ex* e : outputs) sharer.Number(*e);
  return sharer.Finish(outputs, prefix, reserved);
}

GiNaC::ex Inline(const SharedSubexpressions& shared, const GiNaC::ex& e) {
  GiNaC::ex out = e;
  for (auto it = shared.definitions.rbegin(); it != shared.definitions.rend(); ++it) {
    out = out.subs(it->first == it->second);
  }
  return out;
}

}  // namespace hybridtest::symbolic
