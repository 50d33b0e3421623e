#pragma once
// Reading user YAML with errors that say where (file:line and key path), what was expected,
// what was given, and how to fix it. Used by every config reader in io/.
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::io {

class YamlInput {
 public:
  // Parses `path`. Throws ConfigError if the file is missing or not valid YAML (with line).
  static YamlInput FromFile(const std::string& path);
  // Parses text (for tests and inline configs); `path` is only used in messages.
  static YamlInput FromText(const std::string& text, const std::string& path);

  const YAML::Node& root() const { return root_; }
  const std::string& path() const { return path_; }
  const std::string& text() const { return text_; }

  // "file.yaml:12: integrator.dt"
  std::string Where(const YAML::Node& node, std::string_view key_path) const;
  // Throws ConfigError if `node` (a mapping at key_path) has a key not in `allowed`.
  void CheckKeys(const YAML::Node& node, std::string_view key_path,
                 std::initializer_list<std::string_view> allowed) const;
  // A mapping child or an undefined node; throws if present but not a mapping.
  YAML::Node Mapping(const YAML::Node& parent, std::string_view key, std::string_view key_path,
                     bool required) const;
  // A finite number; `expected` describes it ("a positive time step in seconds").
  double Number(const YAML::Node& node, std::string_view key_path, std::string_view expected) const;
  double PositiveNumber(const YAML::Node& node, std::string_view key_path,
                        std::string_view expected) const;
  int Integer(const YAML::Node& node, std::string_view key_path, std::string_view expected) const;
  std::string String(const YAML::Node& node, std::string_view key_path,
                     std::string_view expected) const;
  std::vector<double> Numbers(const YAML::Node& node, std::string_view key_path,
                              std::string_view expected) const;

 private:
  std::string path_;
  std::string text_;
  YAML::Node root_;
};

}  // namespace hybridtest::io
