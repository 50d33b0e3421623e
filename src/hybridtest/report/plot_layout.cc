#include "hybridtest/report/plot_layout.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/report/json_text.h"

namespace hybridtest::report {
namespace {

// True for prefix followed by one or more digits ("q12" with prefix 'q').
bool IsIndexed(const std::string& name, char prefix) {
  return name.size() >= 2 && name[0] == prefix &&
         std::all_of(name.begin() + 1, name.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// The coordinate channel a slot acts on, from a "coordinate" entry: a name or a 0-based index.
std::string CoordinateOf(const nlohmann::json& entry, const std::vector<std::string>& coordinates) {
  if (!entry.is_object() || !entry.contains("coordinate")) return "";
  const nlohmann::json& c = entry["coordinate"];
  if (c.is_string()) return c.get<std::string>();
  if (c.is_number_integer()) {
    const auto index = c.get<long>();
    if (index >= 0 && index < static_cast<long>(coordinates.size())) {
      return coordinates[static_cast<std::size_t>(index)];
    }
  }
  return "";
}

// The coordinate of slot, by the rules in the header.
std::string SlotCoordinate(const nlohmann::json& substructure, const std::string& slot,
                           const nlohmann::json& model, const RunLayout& layout) {
  std::string coordinate = CoordinateOf(substructure, layout.coordinates);
  if (coordinate.empty() && model.is_object() && model.contains("slots") &&
      model["slots"].is_array()) {
    for (const nlohmann::json& s : model["slots"]) {
      if (StringOr(s, "name", "") == slot) coordinate = CoordinateOf(s, layout.coordinates);
    }
  }
  if (coordinate.empty() && IsIndexed(slot, 'r')) {
    const std::string guess = fmt::format("q{}", slot.substr(1));
    if (std::find(layout.coordinates.begin(), layout.coordinates.end(), guess) !=
        layout.coordinates.end()) {
      coordinate = guess;
    }
  }
  return coordinate;
}

}  // namespace

int FindChannel(const io::RunData& run, const std::string& name) {
  for (std::size_t i = 0; i < run.channels.size(); ++i) {
    if (run.channels[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string ChannelUnit(const io::RunData& run, const std::string& name) {
  const int column = FindChannel(run, name);
  return column < 0 ? std::string() : run.channels[static_cast<std::size_t>(column)].unit;
}

std::string UnitSuffix(const io::RunData& run, const std::string& name) {
  const std::string unit = ChannelUnit(run, name);
  return unit.empty() ? " [unit not recorded]" : " [" + unit + "]";
}

Eigen::VectorXd ChannelValues(const io::RunData& run, const std::string& name) {
  const int column = FindChannel(run, name);
  if (column < 0 || column >= run.values.cols()) {
    throw IoError(run.csv_path + ": expected a channel named '" + name +
                  "' in the CSV header, found none; was the run written by hybridtest?");
  }
  return run.values.col(column);
}

std::string RunName(const io::RunData& run) {
  return std::filesystem::path(run.csv_path).stem().string();
}

RunLayout DescribeRun(const io::RunData& run) {
  RunLayout layout;
  layout.name = RunName(run);
  const nlohmann::json& meta = run.metadata;
  const nlohmann::json model =
      meta.is_object() && meta.contains("model") ? meta["model"] : nlohmann::json();
  // The model's own names where the sidecar lists them, else the q/u/r naming convention.
  const auto named = [&](const char* key, char prefix, std::vector<std::string>& out) {
    if (model.is_object() && model.contains(key) && model[key].is_array()) {
      for (const nlohmann::json& entry : model[key]) {
        const std::string name = StringOr(entry, "name", "");
        if (!name.empty() && FindChannel(run, name) >= 0) out.push_back(name);
      }
    }
    if (!out.empty()) return;
    for (const io::Channel& channel : run.channels) {
      if (IsIndexed(channel.name, prefix)) out.push_back(channel.name);
    }
  };
  named("coordinates", 'q', layout.coordinates);
  named("speeds", 'u', layout.speeds);
  named("slots", 'r', layout.restoring);
  if (!meta.is_object()) return layout;
  layout.model_name = StringOr(model, "name", "");

  // The rotor: blades q1..qN and hub speed u<N+1>.
  layout.is_rotor = Lower(layout.model_name).find("rotor") != std::string::npos &&
                    !layout.coordinates.empty();
  if (layout.is_rotor) {
    std::size_t blades = layout.coordinates.size() - 1;
    if (model.contains("slots") && model["slots"].is_array() && !model["slots"].empty()) {
      blades = std::min(model["slots"].size(), layout.coordinates.size());
    }
    layout.blades.assign(layout.coordinates.begin(),
                         layout.coordinates.begin() + static_cast<long>(blades));
    const std::string hub = fmt::format("u{}", blades + 1);
    if (FindChannel(run, hub) >= 0) layout.hub_speed = hub;
  }

  // Physical substructures, their coordinates and their actuator channels.
  if (!meta.contains("substructures") || !meta["substructures"].is_array()) return layout;
  for (const nlohmann::json& s : meta["substructures"]) {
    const std::string slot = StringOr(s, "slot", "");
    layout.slot_coordinates[slot] = SlotCoordinate(s, slot, model, layout);
    if (s.contains("slots") && s["slots"].is_array()) {
      // A substructure that serves several slots: each slot's own coordinate, from the model.
      for (const nlohmann::json& name : s["slots"]) {
        if (!name.is_string()) continue;
        const std::string served = name.get<std::string>();
        layout.slot_coordinates[served] = SlotCoordinate(nlohmann::json(), served, model, layout);
      }
    }
    if (StringOr(s, "kind", "") != "physical") continue;
    PhysicalChannels p;
    p.slot = StringOr(s, "slot", "");
    p.description = StringOr(s, "description", "");
    p.coordinate = SlotCoordinate(s, p.slot, model, layout);
    if (!p.coordinate.empty()) layout.physical_coordinates.insert(p.coordinate);
    const nlohmann::json channels = s.contains("channels") ? s["channels"] : nlohmann::json();
    auto channel = [&](const nlohmann::json& group, const std::string& prefix, const char* key) {
      const std::string name = StringOr(group, key, prefix + "_" + key);
      return FindChannel(run, name) >= 0 ? name : std::string();
    };
    if (channels.is_array()) {
      // Several actuators: one group of channels (and figures) per actuator, "<slot>_a<k>".
      for (std::size_t k = 0; k < channels.size(); ++k) {
        PhysicalChannels a = p;
        a.slot = fmt::format("{}_a{}", p.slot, k + 1);
        a.substructure = p.slot;
        a.actuator = static_cast<int>(k);
        a.coordinate.clear();
        a.command = channel(channels[k], a.slot, "command");
        a.position = channel(channels[k], a.slot, "position");
        a.force = channel(channels[k], a.slot, "force");
        a.lab_time = channel(channels[k], a.slot, "lab_time");
        layout.physical.push_back(a);
      }
      continue;
    }
    p.command = channel(channels, p.slot, "command");
    p.position = channel(channels, p.slot, "position");
    p.force = channel(channels, p.slot, "force");
    p.lab_time = channel(channels, p.slot, "lab_time");
    layout.physical.push_back(p);
  }
  return layout;
}

}  // namespace hybridtest::report
