#pragma once
// The one reader of user YAML in hybridtest: run configs (io/), bench configs (transfer/) and
// restoring-force laws (constitutive/) all read through it. Every error is a ConfigError that
// says where (file:line when known, and the key path), what was expected, what was given and
// how to fix it, e.g.
//   run.yaml:12: integrator.dt = 'abc': expected a positive time step in seconds
//   bench.yaml: bench.actuator.delay_ms (line 7) = 'soon': expected a non-negative delay in ms
//   t.yaml: bench.specimen.stiffness: missing; expected a stiffness in N/m; add `stiffness:` ...
//
// A YamlInput either owns a parsed file (FromFile, FromText: places print "file:line: key") or
// reads a node of a document parsed elsewhere (ForNode: the key paths the caller passes carry
// the whole location, such as "bench.yaml: bench", and the line is appended "(line N)").
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest {

// "parent.key", or "key" when `parent` is empty.
std::string JoinKeyPath(std::string_view parent, std::string_view key);

// Input size limits: a config is a few kilobytes; these bounds keep a mistaken or hostile
// file from exhausting memory before a clear error is given.
inline constexpr std::size_t kMaxConfigBytes = 4u << 20;  // a YAML file. Unit: [bytes].
inline constexpr std::size_t kMaxListLength = 100000;     // entries of one list

class YamlInput {
 public:
  // Parses the file at `path`. Throws ConfigError if it cannot be read, is larger than
  // kMaxConfigBytes, is not UTF-8 (nor is its path), is not valid YAML (with
  // line and column) or is not a mapping at the top level; `top_level_hint` names the expected
  // top-level keys in that message ("keys such as model:, integrator:, duration:").
  static YamlInput FromFile(const std::string& path,
                            std::string_view top_level_hint = "key: value lines");
  // Parses `text` (tests, inline configs); `path` is only used in messages.
  static YamlInput FromText(const std::string& text, const std::string& path,
                            std::string_view top_level_hint = "key: value lines");
  // Reads `node`, part of a document parsed elsewhere whose file is named by the key paths.
  static YamlInput ForNode(const YAML::Node& node);

  const YAML::Node& root() const { return root_; }
  const std::string& path() const { return path_; }  // empty for ForNode
  const std::string& text() const { return text_; }  // empty for ForNode

  // The place of `node` for messages: "file.yaml:12: integrator.dt" (FromFile/FromText) or
  // "bench.yaml: bench.seed (line 12)" (ForNode, key_path "bench.yaml: bench.seed").
  std::string Where(const YAML::Node& node, std::string_view key_path) const;

  // Throws ConfigError "<where> = '<node as given>': expected <expected>" (or "missing" when
  // `node` is absent). For values that parse but are not allowed (an unknown type name, ...).
  [[noreturn]] void ThrowValue(const YAML::Node& node, std::string_view key_path,
                               std::string_view expected) const;

  // Throws ConfigError unless `node` is a mapping.
  void RequireMapping(const YAML::Node& node, std::string_view key_path) const;
  // Throws ConfigError naming the first key of the mapping `node` not in `allowed` (typos).
  void CheckKeys(const YAML::Node& node, std::string_view key_path,
                 std::initializer_list<std::string_view> allowed) const;
  // parent[key] if it is a mapping; an undefined node if absent or empty and not `required`.
  // `key_path` is the path of the child. Throws if present but not a mapping.
  YAML::Node Mapping(const YAML::Node& parent, std::string_view key, std::string_view key_path,
                     bool required) const;

  // The value of `node` at `key_path`. `expected` describes it with its unit ("a positive time
  // step in seconds"). Throws ConfigError when absent, empty or of the wrong kind.
  double Number(const YAML::Node& node, std::string_view key_path,
                std::string_view expected) const;  // finite
  double PositiveNumber(const YAML::Node& node, std::string_view key_path,
                        std::string_view expected) const;
  int Integer(const YAML::Node& node, std::string_view key_path, std::string_view expected) const;
  // A whole number in [min, max] (a count, an index, a seed). Throws ConfigError naming the
  // range when the value is fractional or out of range (e.g. `seed: 1e30`).
  long long Count(const YAML::Node& node, std::string_view key_path, std::string_view expected,
                  long long min, long long max) const;
  std::string String(const YAML::Node& node, std::string_view key_path,
                     std::string_view expected) const;  // any scalar
  std::vector<double> Numbers(const YAML::Node& node, std::string_view key_path,
                              std::string_view expected) const;  // a list of finite numbers

  // The same by key: parent[key], whose key path is JoinKeyPath(parent_path, key).
  double ReadNumber(const YAML::Node& parent, std::string_view parent_path, const std::string& key,
                    std::string_view expected) const;
  // As above, but `fallback` when the key is absent.
  double ReadNumber(const YAML::Node& parent, std::string_view parent_path, const std::string& key,
                    std::string_view expected, double fallback) const;
  // The scalar parent[key], or `fallback` when the key is absent.
  std::string ReadString(const YAML::Node& parent, std::string_view parent_path,
                         const std::string& key, std::string_view fallback) const;

 private:
  [[noreturn]] void ThrowMissing(const YAML::Node& node, std::string_view key_path,
                                 std::string_view expected) const;

  std::string path_;
  std::string text_;
  YAML::Node root_;
};

}  // namespace hybridtest
