// See yaml_input.h.
#include "hybridtest/common/yaml_input.h"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/common/text.h"

namespace hybridtest {
namespace {

bool IsAbsent(const YAML::Node& node) { return !node.IsDefined() || node.IsNull(); }

// The node as the user wrote it, on one line: "abc", "[1, 2]", "{a: 1}".
std::string Given(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

std::string AllowedList(std::initializer_list<std::string_view> allowed) {
  std::string list;
  for (std::string_view a : allowed) list += fmt::format("{}{}", list.empty() ? "" : ", ", a);
  return list;
}

// Refuses a list longer than kMaxListLength, and a mapping that names the same key twice (yaml-cpp keeps both and a lookup finds the
// first, so `force_hard: 60` then `force_hard: 10000` would silently mean 60). Iterative: the
// depth of a document is bounded by its size, not by the stack.
void CheckNoDuplicateKeys(const YAML::Node& root, const std::string& path) {
  // Aliases share nodes, so a small hostile file can name billions of them: bound the walk.
  constexpr long kMaxNodes = 4'000'000;
  long visited = 0;
  // Each node with its key path ("initial_state.q", "a[2]"), for the messages.
  std::vector<std::pair<YAML::Node, std::string>> pending{{root, ""}};
  while (!pending.empty()) {
    if (++visited > kMaxNodes) {
      throw ConfigError(fmt::format("{}: more than {} YAML nodes once aliases (*name) are "
                                    "expanded; a configuration has a few hundred: remove the "
                                    "aliases", path, kMaxNodes));
    }
    const YAML::Node node = pending.back().first;
    const std::string key_path = std::move(pending.back().second);
    pending.pop_back();
    if (node.IsSequence()) {
      // Every list of every file is bounded here, whichever reader takes it later.
      if (node.size() > kMaxListLength) {
        throw ConfigError(fmt::format("{}:{}: {}: a list of {} entries; at most {} are allowed "
                                      "in one list (docs/safety.md, \"Counts and sizes\"): "
                                      "shorten it", path, node.Mark().line + 1,
                                      key_path.empty() ? "(top level)" : key_path, node.size(),
                                      kMaxListLength));
      }
      for (std::size_t i = 0; i < node.size(); ++i) {
        pending.emplace_back(node[i], fmt::format("{}[{}]", key_path, i));
      }
      continue;
    }
    if (!node.IsMap()) continue;
    std::map<std::string, int> lines;
    for (const auto& kv : node) {
      std::string key = "?";
      if (kv.first.IsScalar()) {
        key = kv.first.Scalar();
        const int line = kv.first.Mark().line + 1;
        const auto [it, inserted] = lines.emplace(key, line);
        if (!inserted) {
          throw ConfigError(fmt::format(
              "{}:{}: the key '{}' appears twice in one mapping (lines {} and {}); a YAML "
              "mapping holds each key once: delete one of them", path, line, key,
              it->second, line));
        }
      }
      pending.emplace_back(kv.second, JoinKeyPath(key_path, key));
    }
  }
}

}  // namespace

std::string JoinKeyPath(std::string_view parent, std::string_view key) {
  if (parent.empty()) return std::string(key);
  return fmt::format("{}.{}", parent, key);
}

YamlInput YamlInput::FromFile(const std::string& path, std::string_view top_level_hint) {
  if (const std::string bad = FindInvalidUtf8(path); !bad.empty()) {
    throw ConfigError(fmt::format("{}: the file name is not valid UTF-8 (at {}); rename the file "
                                  "with UTF-8 characters only", Printable(path), bad));
  }
  // A FIFO, a device or a directory given by mistake must not hang or feed the parser.
  const std::string text = ReadInputFile(path, "", "YAML file", kMaxConfigBytes);
  return FromText(text, path, top_level_hint);
}

YamlInput YamlInput::FromText(const std::string& text, const std::string& path,
                              std::string_view top_level_hint) {
  YamlInput input;
  input.path_ = path;
  input.text_ = text;
  if (const std::string bad = FindInvalidUtf8(text); !bad.empty()) {
    throw ConfigError(fmt::format("{}: not valid UTF-8 at {}; save the file as UTF-8 (check for "
                                  "characters pasted from another encoding)", Printable(path),
                                  bad));
  }
  try {
    input.root_ = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("{}:{}:{}: not valid YAML: {}; fix the syntax there (check the "
                                  "indentation, a missing ':' or an unclosed bracket or quote)",
                                  path, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  CheckNoDuplicateKeys(input.root_, path);
  if (!input.root_.IsMap()) {
    throw ConfigError(fmt::format("{}: expected a YAML mapping at the top level ({}), got '{}'",
                                  path, top_level_hint, Given(input.root_)));
  }
  return input;
}

YamlInput YamlInput::ForNode(const YAML::Node& node) {
  YamlInput input;
  // An absent key of a const node is an invalid node, which yaml-cpp refuses to assign (found
  // by fuzzing); the caller's RequireMapping then reports it as missing.
  if (node.IsDefined()) input.root_ = node;
  return input;
}

namespace {
// Line (1-based) of the deepest node of root that exists along `key_path` ("a.b[2].c"), 0 if
// none: a missing key is reported at the mapping that should hold it.
int DeepestLine(const YAML::Node& root, std::string_view key_path) {
  if (!root.IsDefined() || key_path.empty()) return 0;
  YAML::Node node(root);  // shares root's data; rebound with reset(), never assigned
  int line = node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
  std::size_t start = 0;
  while (start <= key_path.size()) {
    const std::size_t dot = key_path.find('.', start);
    std::string key(key_path.substr(start, dot == std::string_view::npos ? std::string_view::npos
                                                                          : dot - start));
    if (const auto bracket = key.find('['); bracket != std::string::npos) key.resize(bracket);
    if (!node.IsMap()) break;
    const YAML::Node child = static_cast<const YAML::Node&>(node)[key];  // const: no insertion
    if (!child.IsDefined()) break;
    if (child.Mark().line >= 0) line = child.Mark().line + 1;
    node.reset(child);
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return line;
}
}  // namespace

std::string YamlInput::Where(const YAML::Node& node, std::string_view key_path) const {
  const bool defined = node.IsDefined() && node.Mark().line >= 0;
  // A fragment (no file of its own) carries the caller's key path: only a file is walked.
  const int line = defined ? node.Mark().line + 1 : path_.empty() ? 0 : DeepestLine(root_, key_path);
  const bool has_line = line > 0;
  if (path_.empty()) {
    const std::string_view kp = key_path.empty() ? std::string_view("(top level)") : key_path;
    return has_line ? fmt::format("{} (line {})", kp, line) : std::string(kp);
  }
  const std::string file = has_line ? fmt::format("{}:{}", path_, line) : path_;
  return key_path.empty() ? file : fmt::format("{}: {}", file, key_path);
}

void YamlInput::ThrowMissing(const YAML::Node& node, std::string_view key_path,
                             std::string_view expected) const {
  // How to fix it: name the key to add and the mapping to add it to.
  std::string fix;
  const std::size_t dot = key_path.rfind('.');
  const std::string_view key = dot == std::string_view::npos ? key_path : key_path.substr(dot + 1);
  if (!key.empty() && key.find_first_of(" :[") == std::string_view::npos) {
    const std::string_view parent = dot == std::string_view::npos ? "" : key_path.substr(0, dot);
    if (node.IsDefined()) {
      fix = fmt::format("; give `{}:` a value", key);
    } else {
      fix = fmt::format("; add `{}: ...` {}", key,
                        parent.empty() ? std::string("at the top level")
                                       : fmt::format("under {}", parent));
    }
  }
  throw ConfigError(fmt::format("{}: {}; expected {}{}", Where(node, key_path),
                                node.IsDefined() ? "empty" : "missing", expected, fix));
}

void YamlInput::ThrowValue(const YAML::Node& node, std::string_view key_path,
                           std::string_view expected) const {
  if (IsAbsent(node)) ThrowMissing(node, key_path, expected);
  throw ConfigError(fmt::format("{} = '{}': expected {}", Where(node, key_path), Given(node),
                                expected));
}

void YamlInput::RequireMapping(const YAML::Node& node, std::string_view key_path) const {
  if (node.IsDefined() && node.IsMap()) return;
  ThrowValue(node, key_path, "a mapping (key: value lines); check the indentation");
}

void YamlInput::CheckKeys(const YAML::Node& node, std::string_view key_path,
                          std::initializer_list<std::string_view> allowed) const {
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : Given(kv.first);
    bool known = false;
    for (std::string_view a : allowed) known = known || a == key;
    if (known) continue;
    // `{description: a, b}`: in a {...} mapping a comma ends the value, so the rest of an
    // unquoted text becomes a key without a value. (The style is not tested: a node copied
    // by the model file's repetition loses it.)
    const bool cut_text = kv.second.IsNull();
    throw ConfigError(fmt::format(
        "{}: unknown key '{}'; expected one of: {} ({})",
        Where(kv.first, JoinKeyPath(key_path, key)), key, AllowedList(allowed),
        cut_text ? "it has no value: inside {...} a comma ends a value, so if this is the rest "
                   "of a text, put the whole text in quotes, e.g. description: \"a, b\"; else "
                   "check the spelling and the indentation"
                 : "check the spelling and the indentation"));
  }
}

YAML::Node YamlInput::Mapping(const YAML::Node& parent, std::string_view key,
                              std::string_view key_path, bool required) const {
  const YAML::Node node = parent[std::string(key)];
  if (IsAbsent(node)) {
    if (required) {
      throw ConfigError(fmt::format("{}: missing required section '{}:'; add it with its "
                                    "entries (key: value lines)",
                                    Where(node.IsDefined() ? node : parent, key_path), key));
    }
    return YAML::Node(YAML::NodeType::Undefined);
  }
  RequireMapping(node, key_path);
  return node;
}

double YamlInput::Number(const YAML::Node& node, std::string_view key_path,
                         std::string_view expected) const {
  if (IsAbsent(node)) ThrowMissing(node, key_path, expected);
  double value = 0.0;
  bool ok = node.IsScalar();
  if (ok) {
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (!ok || !std::isfinite(value)) ThrowValue(node, key_path, expected);
  return value;
}

double YamlInput::PositiveNumber(const YAML::Node& node, std::string_view key_path,
                                 std::string_view expected) const {
  const double value = Number(node, key_path, expected);
  if (!(value > 0.0)) ThrowValue(node, key_path, expected);
  return value;
}

int YamlInput::Integer(const YAML::Node& node, std::string_view key_path,
                       std::string_view expected) const {
  const double value = Number(node, key_path, expected);
  if (value != std::floor(value) || std::abs(value) > 1e9) ThrowValue(node, key_path, expected);
  return static_cast<int>(value);
}

long long YamlInput::Count(const YAML::Node& node, std::string_view key_path,
                           std::string_view expected, long long min, long long max) const {
  const double value = Number(node, key_path, expected);
  if (value != std::floor(value) || value < static_cast<double>(min) ||
      value > static_cast<double>(max)) {
    ThrowValue(node, key_path, fmt::format("{} from {} to {}", expected, min, max));
  }
  return static_cast<long long>(value);
}

std::string YamlInput::String(const YAML::Node& node, std::string_view key_path,
                              std::string_view expected) const {
  if (IsAbsent(node)) ThrowMissing(node, key_path, expected);
  if (!node.IsScalar()) ThrowValue(node, key_path, expected);
  return node.Scalar();
}

std::vector<double> YamlInput::Numbers(const YAML::Node& node, std::string_view key_path,
                                       std::string_view expected) const {
  if (IsAbsent(node) || !node.IsSequence()) {
    ThrowValue(node, key_path, fmt::format("a list [a, b, ...] of {}", expected));
  }
  if (node.size() > kMaxListLength) {
    throw ConfigError(fmt::format("{}: a list of {} entries; at most {} are allowed",
                                  Where(node, key_path), node.size(), kMaxListLength));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(Number(node[i], fmt::format("{}[{}]", key_path, i), expected));
  }
  return values;
}

double YamlInput::ReadNumber(const YAML::Node& parent, std::string_view parent_path,
                             const std::string& key, std::string_view expected) const {
  return Number(parent[key], JoinKeyPath(parent_path, key), expected);
}

double YamlInput::ReadNumber(const YAML::Node& parent, std::string_view parent_path,
                             const std::string& key, std::string_view expected,
                             double fallback) const {
  if (!parent[key].IsDefined()) return fallback;
  return ReadNumber(parent, parent_path, key, expected);
}

std::string YamlInput::ReadString(const YAML::Node& parent, std::string_view parent_path,
                                  const std::string& key, std::string_view fallback) const {
  const YAML::Node field = parent[key];
  if (!field.IsDefined()) return std::string(fallback);
  return String(field, JoinKeyPath(parent_path, key), "a word (a YAML scalar)");
}

}  // namespace hybridtest
