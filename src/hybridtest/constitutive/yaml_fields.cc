#include "hybridtest/constitutive/yaml_fields.h"

#include <cmath>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {
namespace {

std::string LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return "";
  return fmt::format(" (line {})", mark.line + 1);
}

}  // namespace

std::string JoinKeyPath(std::string_view where, std::string_view key) {
  if (where.empty()) return std::string(key);
  return fmt::format("{}.{}", where, key);
}

void ThrowField(const YAML::Node& node, std::string_view where, std::string_view key,
                std::string_view value, std::string_view expectation) {
  throw ConfigError(fmt::format("{}{} = '{}': expected {}", JoinKeyPath(where, key),
                                node ? LineOf(node) : std::string(), value, expectation));
}

void RequireMapping(const YAML::Node& node, std::string_view where) {
  if (!node || !node.IsMap()) {
    throw ConfigError(fmt::format("{}{}: expected a mapping (key: value lines); check the "
                                  "indentation",
                                  where, node ? LineOf(node) : std::string()));
  }
}

void RequireKnownKeys(const YAML::Node& node, std::string_view where,
                      std::initializer_list<std::string_view> allowed) {
  for (const auto& entry : node) {
    const auto key = entry.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const auto& name : allowed) {
      known = known || key == name;
      list += list.empty() ? std::string(name) : fmt::format(", {}", name);
    }
    if (!known) {
      throw ConfigError(fmt::format("{}{}: unknown key; expected one of: {}",
                                    JoinKeyPath(where, key), LineOf(entry.first), list));
    }
  }
}

double ReadNumber(const YAML::Node& node, std::string_view where, const std::string& key,
                  std::string_view expectation) {
  const YAML::Node field = node[key];
  if (!field) {
    throw ConfigError(fmt::format("{}: missing; expected {}. Add the key under {}",
                                  JoinKeyPath(where, key), expectation,
                                  where.empty() ? "the top level" : where));
  }
  if (!field.IsScalar()) ThrowField(field, where, key, "(not a scalar)", expectation);
  double value = 0.0;
  try {
    value = field.as<double>();
  } catch (const YAML::Exception&) {
    ThrowField(field, where, key, field.Scalar(), expectation);
  }
  if (!std::isfinite(value)) ThrowField(field, where, key, field.Scalar(), expectation);
  return value;
}

double ReadNumber(const YAML::Node& node, std::string_view where, const std::string& key,
                  std::string_view expectation, double fallback) {
  if (!node[key]) return fallback;
  return ReadNumber(node, where, key, expectation);
}

std::string ReadString(const YAML::Node& node, std::string_view where, const std::string& key,
                       std::string_view fallback) {
  const YAML::Node field = node[key];
  if (!field) return std::string(fallback);
  if (!field.IsScalar()) ThrowField(field, where, key, "(not a scalar)", "a word");
  return field.Scalar();
}

}  // namespace hybridtest::constitutive
