// Channel naming convention (docs/results-format.md): classification of a channel by its name
// and the units and descriptions inferred from it. Declared in run_reader.h.
#include <fmt/format.h>

#include <array>
#include <charconv>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::io {
namespace {

// n if `name` is `prefix` followed by a positive decimal number, else 0.
int IndexAfter(std::string_view name, char prefix) {
  if (name.size() < 2 || name.front() != prefix || name[1] == '0') return 0;
  int index = 0;
  const auto result = std::from_chars(name.data() + 1, name.data() + name.size(), index);
  if (result.ec != std::errc() || result.ptr != name.data() + name.size()) return 0;
  return index;
}

constexpr std::array<std::string_view, 4> kPhysicalFields = {"command", "position", "force",
                                                             "lab_time"};

}  // namespace

ChannelClass ClassifyChannel(std::string_view name) {
  ChannelClass result;
  if (name == "t") {
    result.kind = ChannelKind::kTime;
    return result;
  }
  // Physical-substructure channels: <slot>_<field>, with the longest matching field suffix.
  for (const auto field : kPhysicalFields) {
    if (name.size() > field.size() + 1 && name.ends_with(field) &&
        name[name.size() - field.size() - 1] == '_') {
      result.kind = ChannelKind::kPhysical;
      result.slot = std::string(name.substr(0, name.size() - field.size() - 1));
      result.field = std::string(field);
      return result;
    }
  }
  const std::array<std::pair<char, ChannelKind>, 3> indexed = {
      std::pair{'q', ChannelKind::kCoordinate}, std::pair{'u', ChannelKind::kSpeed},
      std::pair{'r', ChannelKind::kRestoringForce}};
  for (const auto& [prefix, kind] : indexed) {
    if (const int index = IndexAfter(name, prefix); index > 0) {
      result.kind = kind;
      result.index = index;
      return result;
    }
  }
  return result;
}

std::string InferChannelUnit(std::string_view name) {
  const ChannelClass c = ClassifyChannel(name);
  switch (c.kind) {
    case ChannelKind::kTime: return "s";
    case ChannelKind::kCoordinate: return "m";
    case ChannelKind::kSpeed: return "m/s";
    case ChannelKind::kRestoringForce: return "N";
    case ChannelKind::kPhysical:
      if (c.field == "force") return "N";
      if (c.field == "lab_time") return "s";
      return "m";  // command, position
    case ChannelKind::kOther: break;
  }
  return "";
}

std::string InferChannelDescription(std::string_view name) {
  const ChannelClass c = ClassifyChannel(name);
  switch (c.kind) {
    case ChannelKind::kTime: return "simulated time";
    case ChannelKind::kCoordinate: return fmt::format("generalized coordinate {}", c.index);
    case ChannelKind::kSpeed: return fmt::format("generalized speed {}", c.index);
    case ChannelKind::kRestoringForce: return fmt::format("restoring force {}", c.index);
    case ChannelKind::kPhysical:
      if (c.field == "command") return fmt::format("actuator command of slot {}", c.slot);
      if (c.field == "position") return fmt::format("measured position of slot {}", c.slot);
      if (c.field == "force") return fmt::format("measured force of slot {}", c.slot);
      return fmt::format("cumulative lab time of slot {}", c.slot);
    case ChannelKind::kOther: break;
  }
  return "";
}

}  // namespace hybridtest::io
