#include "hybridtest/transfer/bench_faults.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

constexpr std::array<std::pair<FaultKind, const char*>, 8> kKinds = {{
    {FaultKind::kNan, "nan"},
    {FaultKind::kInf, "inf"},
    {FaultKind::kSpike, "spike"},
    {FaultKind::kSilence, "silence"},
    {FaultKind::kCorrupt, "corrupt"},
    {FaultKind::kStaleSeq, "stale_seq"},
    {FaultKind::kDuplicate, "duplicate"},
    {FaultKind::kClose, "close"},
}};

constexpr const char* kKindList =
    "nan, inf, spike, silence, corrupt, stale_seq, duplicate, close";

}  // namespace

std::string FaultKindName(FaultKind kind) {
  for (const auto& [k, name] : kKinds) {
    if (k == kind) return name;
  }
  return "unknown";
}

FaultKind ParseFaultKind(const std::string& name, const std::string& where) {
  const auto it = std::find_if(kKinds.begin(), kKinds.end(),
                               [&](const auto& entry) { return name == entry.second; });
  if (it == kKinds.end()) {
    throw ConfigError(fmt::format("{}: unknown fault kind '{}'; expected one of {}", where, name,
                                  kKindList));
  }
  return it->first;
}

Fault ParseFault(const std::string& text, const std::string& where) {
  const auto fail = [&](const std::string& why) {
    return ConfigError(fmt::format(
        "{} = '{}': {}; expected KIND@N with KIND one of {} and N the 1-based command index "
        "(e.g. spike@3)",
        where, text, why, kKindList));
  };
  const auto at = text.find('@');
  if (at == std::string::npos) throw fail("no '@'");
  const std::string kind = text.substr(0, at);
  const std::string index = text.substr(at + 1);
  Fault fault;
  try {
    fault.kind = ParseFaultKind(kind, where);
  } catch (const ConfigError&) {
    throw fail(fmt::format("unknown fault kind '{}'", kind));
  }
  if (index.empty() || index.size() > 12 ||
      index.find_first_not_of("0123456789") != std::string::npos) {
    throw fail("the command index is not a positive integer");
  }
  fault.command = std::stol(index);
  if (fault.command < 1) throw fail("the command index must be at least 1");
  return fault;
}

const Fault* FindFault(const std::vector<Fault>& faults, FaultKind kind, long command) {
  const auto it = std::find_if(faults.begin(), faults.end(), [&](const Fault& f) {
    return f.kind == kind && f.command == command;
  });
  return it == faults.end() ? nullptr : &*it;
}

bool HasFault(const std::vector<Fault>& faults, FaultKind kind, long command) {
  return FindFault(faults, kind, command) != nullptr;
}

void ApplyMeasurementFaults(const std::vector<Fault>& faults, long command,
                            const BenchUnits& units, Measurement& measurement) {
  if (HasFault(faults, FaultKind::kNan, command)) {
    measurement.force = std::numeric_limits<double>::quiet_NaN();
  }
  if (HasFault(faults, FaultKind::kInf, command)) {
    measurement.force = std::numeric_limits<double>::infinity();
  }
  if (const Fault* spike = FindFault(faults, FaultKind::kSpike, command)) {
    measurement.force += spike->spike_force / units.newtons_per_force_unit;
  }
}

}  // namespace hybridtest::transfer
