// The `modes:` section of a model file. See model_file_modes.h.
#include "hybridtest/modelfile/model_file_modes.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/names.h"

namespace hybridtest::modelfile {

namespace {

bool ReadBool(const YamlInput& in, const YAML::Node& node, const std::string& kp) {
  const std::string text = in.String(node, kp, "true or false");
  if (text == "true") return true;
  if (text == "false") return false;
  in.ThrowValue(node, kp, "true (a complex pair, Im λ ≠ 0) or false (a real eigenvalue)");
}

void CheckUnique(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                 const std::vector<std::string>& seen, const std::string& name) {
  if (std::find(seen.begin(), seen.end(), name) != seen.end()) {
    throw ConfigError(fmt::format("{}: '{}' is given twice; give each once", in.Where(node, kp),
                                  name));
  }
}

}  // namespace

ModeReading ReadModeReading(const YamlInput& in) {
  ModeReading out;
  const YAML::Node modes = in.Mapping(in.root(), "modes", "modes", false);
  if (!modes.IsDefined()) return out;
  in.CheckKeys(modes, "modes", {"coordinates", "labels"});
  if (const YAML::Node list = modes["coordinates"]; list.IsDefined()) {
    if (!list.IsSequence()) in.ThrowValue(list, "modes.coordinates", "a list of coordinate names");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string kp = fmt::format("modes.coordinates[{}]", i);
      const std::string name = in.String(list[i], kp, "a coordinate's name");
      CheckUnique(in, list[i], kp, out.coordinates, name);
      out.coordinates.push_back(name);
      out.coordinates_where.push_back(in.Where(list[i], kp));
    }
  }
  if (const YAML::Node list = modes["labels"]; list.IsDefined()) {
    if (!list.IsSequence()) {
      in.ThrowValue(list, "modes.labels", "a list of {name: ..., oscillatory: ..., dominant: ...}");
    }
    std::vector<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string kp = fmt::format("modes.labels[{}]", i);
      in.RequireMapping(list[i], kp);
      in.CheckKeys(list[i], kp, {"name", "oscillatory", "dominant"});
      ModeLabel label;
      label.name = in.String(list[i]["name"], kp + ".name", "the mode's name (weave, capsize)");
      CheckName(in, list[i]["name"], kp + ".name", label.name, NameKind::kText);
      CheckUnique(in, list[i]["name"], kp + ".name", names, label.name);
      names.push_back(label.name);
      if (list[i]["oscillatory"]) {
        label.oscillatory = ReadBool(in, list[i]["oscillatory"], kp + ".oscillatory");
      }
      if (list[i]["dominant"]) {
        label.dominant = in.String(list[i]["dominant"], kp + ".dominant", "a coordinate's name");
      }
      label.where = in.Where(list[i], kp);
      out.labels.push_back(std::move(label));
    }
  }
  return out;
}

}  // namespace hybridtest::modelfile
