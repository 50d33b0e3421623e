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

class Hasher {
 public:
  std::uint64_t operator()(const GiNaC::ex& e) {
    const auto it = memo_.find(e);
    if (it != memo_.end()) return it->second;
    std::uint64_t h = kFnvOffset;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      h = Fnv(Fnv(h, "s:"), GiNaC::ex_to<GiNaC::symbol>(e).get_name());
    } else if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) {
      std::ostringstream os;
      os.precision(17);
      os << e;
      h = Fnv(Fnv(h, "n:"), os.str());
    } else {
      std::vector<std::uint64_t> ops;
      for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back((*this)(e.op(i)));
      const bool commutative = GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e);
      if (commutative) std::sort(ops.begin(), ops.end());
      std::string kind = GiNaC::ex_to<GiNaC::basic>(e).class_name();
      if (GiNaC::is_a<GiNaC::function>(e)) kind += ":" + GiNaC::ex_to<GiNaC::function>(e).get_name();
      h = Fnv(h, kind);
      for (std::uint64_t v : ops) h = Mix(h, v);
    }
    memo_.emplace(e, h);
    return h;
  }

 private:
  std::map<GiNaC::ex, std::uint64_t, GiNaC::ex_is_less> memo_;
};

// The operands of e, in canonical order.
std::vector<GiNaC::ex> SortedOperands(const GiNaC::ex& e, Hasher& hash) {
  std::vector<std::pair<std::uint64_t, GiNaC::ex>> ops;
  for (std::size_t i = 0; i < e.nops(); ++i) ops.emplace_back(hash(e.op(i)), e.op(i));
  std::stable_sort(ops.begin(), ops.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
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
  void Count(const GiNaC::ex& e) {
    if (IsLeaf(e)) return;
    const auto [it, fresh] = uses_.try_emplace(e, 0);
    ++it->second;
    if (!fresh) return;
    for (std::size_t i = 0; i < e.nops(); ++i) Count(e.op(i));
  }

  // Numbers the shared subexpressions depth-first, operands in canonical order.
  void Number(const GiNaC::ex& e) {
    if (IsLeaf(e) || !visited_.emplace(e, 0).second) return;
    for (const GiNaC::ex& op : SortedOperands(e, hash_)) Number(op);
    if (uses_[e] >= 2 && !IsTrivial(e)) {
      index_.emplace(e, order_.size());
      order_.push_back(e);
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
    const auto it = index_.find(e);
    if (it != index_.end()) return symbols_[it->second];
    return RebuildBody(e);
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
  return hash(e);
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
