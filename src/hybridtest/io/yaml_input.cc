// See yaml_input.h.
#include "hybridtest/io/yaml_input.h"

#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"

namespace hybridtest::io {

YamlInput YamlInput::FromFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw ConfigError(fmt::format("{}: cannot open the config file (does it exist? paths are "
                                  "relative to the current directory)", path));
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return FromText(buffer.str(), path);
}

YamlInput YamlInput::FromText(const std::string& text, const std::string& path) {
  YamlInput input;
  input.path_ = path;
  input.text_ = text;
  try {
    input.root_ = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("{}:{}:{}: not valid YAML: {}", path, e.mark.line + 1,
                                  e.mark.column + 1, e.msg));
  }
  if (!input.root_.IsMap()) {
    throw ConfigError(fmt::format("{}: expected a YAML mapping at the top level (keys such as "
                                  "model:, integrator:, duration:)", path));
  }
  return input;
}

std::string YamlInput::Where(const YAML::Node& node, std::string_view key_path) const {
  if (node.IsDefined() && node.Mark().line >= 0) {
    return fmt::format("{}:{}: {}", path_, node.Mark().line + 1, key_path);
  }
  return fmt::format("{}: {}", path_, key_path);
}

void YamlInput::CheckKeys(const YAML::Node& node, std::string_view key_path,
                          std::initializer_list<std::string_view> allowed) const {
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    bool ok = false;
    for (std::string_view a : allowed) ok = ok || a == key;
    if (ok) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    const std::string full = key_path.empty() ? key : fmt::format("{}.{}", key_path, key);
    throw ConfigError(fmt::format("{}: unknown key '{}'; expected one of: {}",
                                  Where(kv.first, full), key, list));
  }
}

YAML::Node YamlInput::Mapping(const YAML::Node& parent, std::string_view key,
                              std::string_view key_path, bool required) const {
  const YAML::Node node = parent[std::string(key)];
  if (!node.IsDefined() || node.IsNull()) {
    if (required) {
      throw ConfigError(fmt::format("{}: missing required section '{}:'", Where(parent, key_path),
                                    key));
    }
    return YAML::Node(YAML::NodeType::Undefined);
  }
  if (!node.IsMap()) {
    throw ConfigError(fmt::format("{}: expected a mapping (key: value lines), got '{}'",
                                  Where(node, key_path), YAML::Dump(node)));
  }
  return node;
}

double YamlInput::Number(const YAML::Node& node, std::string_view key_path,
                         std::string_view expected) const {
  if (!node.IsDefined() || node.IsNull()) {
    throw ConfigError(fmt::format("{}: missing; expected {}", Where(node, key_path), expected));
  }
  double value = 0.0;
  bool ok = node.IsScalar();
  if (ok) {
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (!ok || !std::isfinite(value)) {
    throw ConfigError(fmt::format("{} = {}: expected {}", Where(node, key_path), YAML::Dump(node),
                                  expected));
  }
  return value;
}

double YamlInput::PositiveNumber(const YAML::Node& node, std::string_view key_path,
                                 std::string_view expected) const {
  const double value = Number(node, key_path, expected);
  if (!(value > 0.0)) {
    throw ConfigError(fmt::format("{} = {}: expected {}", Where(node, key_path), value, expected));
  }
  return value;
}

int YamlInput::Integer(const YAML::Node& node, std::string_view key_path,
                       std::string_view expected) const {
  const double value = Number(node, key_path, expected);
  if (value != std::floor(value) || std::abs(value) > 1e9) {
    throw ConfigError(fmt::format("{} = {}: expected {}", Where(node, key_path), value, expected));
  }
  return static_cast<int>(value);
}

std::string YamlInput::String(const YAML::Node& node, std::string_view key_path,
                              std::string_view expected) const {
  if (!node.IsDefined() || !node.IsScalar()) {
    throw ConfigError(fmt::format("{}: expected {}", Where(node, key_path), expected));
  }
  return node.as<std::string>();
}

std::vector<double> YamlInput::Numbers(const YAML::Node& node, std::string_view key_path,
                                       std::string_view expected) const {
  if (!node.IsSequence()) {
    throw ConfigError(fmt::format("{}: expected a list [a, b, ...] of {}", Where(node, key_path),
                                  expected));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(Number(node[i], fmt::format("{}[{}]", key_path, i), expected));
  }
  return values;
}

}  // namespace hybridtest::io
