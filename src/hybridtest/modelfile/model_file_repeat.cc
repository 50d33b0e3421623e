// Model files: `repeat:` blocks in list sections, expanded at load time. See file_context.h
// (ListItems) and docs/model-files.md.
#include <fmt/core.h>

#include <cctype>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/file_context.h"

namespace hybridtest::modelfile::internal {

namespace {
// Replaces $var and ${var} by `value` in every scalar under `node` (a clone: marks are kept).
void Substitute(YAML::Node node, const std::string& var, const std::string& value) {
  if (node.IsScalar()) {
    const std::string& s = node.Scalar();
    std::string out;
    bool changed = false;
    for (std::size_t k = 0; k < s.size();) {
      if (s[k] == '$') {
        if (s.compare(k + 1, var.size() + 2, "{" + var + "}") == 0) {
          out += value;
          k += var.size() + 3;
          changed = true;
          continue;
        }
        const std::size_t after = k + 1 + var.size();
        if (s.compare(k + 1, var.size(), var) == 0 &&
            (after >= s.size() || !(std::isalnum(static_cast<unsigned char>(s[after])) || s[after] == '_'))) {
          out += value;
          k = after;
          changed = true;
          continue;
        }
      }
      out += s[k++];
    }
    if (changed) node = out;
  } else if (node.IsSequence()) {
    for (YAML::Node child : node) Substitute(child, var, value);
  } else if (node.IsMap()) {
    for (auto kv : node) Substitute(kv.second, var, value);
  }
}
}  // namespace

std::vector<YAML::Node> ListItems(const YamlInput& in, const YAML::Node& node,
                                  const std::string& key, std::vector<std::string>* labels) {
  std::vector<YAML::Node> out;
  if (!node.IsDefined() || node.IsNull()) return out;
  if (!node.IsSequence()) {
    throw ConfigError(fmt::format("{}: expected a list (lines starting with '- ')",
                                  in.Where(node, key)));
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    const std::string kp = fmt::format("{}[{}]", key, i);
    if (!item.IsMap() || !item["repeat"]) {
      out.push_back(item);
      if (labels != nullptr) labels->push_back(kp);
      continue;
    }
    in.CheckKeys(item, kp, {"repeat", "items"});
    const YAML::Node repeat = item["repeat"];
    if (!repeat.IsMap() || repeat.size() != 1 || !repeat.begin()->second.IsSequence() ||
        repeat.begin()->second.size() == 0) {
      in.ThrowValue(repeat, kp + ".repeat", "one variable and its values, e.g. {i: [1, 2, 3]}");
    }
    const std::string var = repeat.begin()->first.as<std::string>();
    bool name_ok = !var.empty() && !std::isdigit(static_cast<unsigned char>(var[0]));
    for (char ch : var) name_ok = name_ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
    if (!name_ok) {
      throw ConfigError(fmt::format("{}: the repeat variable '{}' must be a name (letters, "
                                    "digits, _), used as ${}", in.Where(repeat, kp + ".repeat"),
                                    var, var));
    }
    const YAML::Node items = item["items"];
    if (!items.IsDefined() || !items.IsSequence()) {
      in.ThrowValue(item["items"], kp + ".items", "the list of elements to repeat");
    }
    // The values, held here: a range over a member of the temporary iterator would dangle.
    const YAML::Node values = repeat.begin()->second;
    for (const auto& v : values) {
      if (!v.IsScalar()) in.ThrowValue(v, kp + ".repeat." + var, "a list of values (numbers or names)");
      // A fresh copy of the items per value, parsed again from the file's text so that every
      // copy keeps the file's line numbers (YAML::Clone loses them).
      const YAML::Node fresh =
          in.text().empty() ? YAML::Node() : static_cast<const YAML::Node>(YAML::Load(in.text()))[key][i]["items"];
      for (std::size_t j = 0; j < items.size(); ++j) {
        const std::string label = fmt::format("{}.items[{}] ({} = {})", kp, j, var, v.Scalar());
        if (items[j].IsMap() && items[j]["repeat"]) {
          throw ConfigError(fmt::format("{}: repeat blocks do not nest; list the combinations "
                                        "in one repeat", in.Where(items[j], label)));
        }
        YAML::Node copy = fresh.IsDefined() && fresh.IsSequence() && fresh.size() == items.size()
                              ? fresh[j]
                              : YAML::Clone(items[j]);
        Substitute(copy, var, v.Scalar());
        out.push_back(copy);
        if (labels != nullptr) labels->push_back(label);
        if (out.size() > kMaxListLength) {
          throw ConfigError(fmt::format("{}: more than {} elements after expansion",
                                        in.Where(item, kp), kMaxListLength));
        }
      }
    }
  }
  return out;
}

}  // namespace hybridtest::modelfile::internal
