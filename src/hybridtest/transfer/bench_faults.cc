#include "hybridtest/transfer/bench_faults.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <utility>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

constexpr std::array<std::pair<FaultKind, const char*>, 7> kKinds = {{
    {FaultKind::kNan, "nan"},
    {FaultKind::kSpike, "spike"},
    {FaultKind::kCorrupt, "corrupt"},
    {FaultKind::kStaleSeq, "stale_seq"},
    {FaultKind::kDuplicate, "duplicate"},
    {FaultKind::kSilence, "silence"},
    {FaultKind::kClose, "close"},
}};

}  // namespace

std::string FaultKindName(FaultKind kind) {
  for (const auto& [k, name] : kKinds) {
    if (k == kind) return name;
  }
  return "unknown";
}

Fault ParseFault(const std::string& text, const std::string& where) {
  const auto fail = [&](const std::string& why) {
    return ConfigError(fmt::format(
        "{} = '{}': {}; expected KIND@N with KIND one of nan, spike, corrupt, stale_seq, "
        "duplicate, silence, close and N the 1-based command index (e.g. spike@3)",
        where, text, why));
  };
  const auto at = text.find('@');
  if (at == std::string::npos) throw fail("no '@'");
  const std::string kind = text.substr(0, at);
  const std::string index = text.substr(at + 1);
  Fault fault;
  const auto it = std::find_if(kKinds.begin(), kKinds.end(),
                               [&](const auto& entry) { return kind == entry.second; });
  if (it == kKinds.end()) throw fail(fmt::format("unknown fault kind '{}'", kind));
  fault.kind = it->first;
  if (index.empty() || index.size() > 9 ||
      index.find_first_not_of("0123456789") != std::string::npos) {
    throw fail("the command index is not a positive integer");
  }
  fault.command = std::stol(index);
  if (fault.command < 1) throw fail("the command index must be at least 1");
  return fault;
}

bool HasFault(const std::vector<Fault>& faults, FaultKind kind, long command) {
  return std::any_of(faults.begin(), faults.end(), [&](const Fault& f) {
    return f.kind == kind && f.command == command;
  });
}

}  // namespace hybridtest::transfer
