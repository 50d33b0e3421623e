// See campaign_file.h.
#include "hybridtest/campaign/campaign_file.h"

#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/csv.h"

namespace hybridtest::campaign {
namespace fs = std::filesystem;
namespace {

using Params = std::vector<std::pair<std::string, std::string>>;

// The most cases a campaign may have (table rows × grid × seeds), checked before the product
// is formed: each case is a run with a folder of its own, so more is a slip (a grid of
// 1,000 values on three keys is 10⁹ cases), not a plan. docs/campaigns.md.
constexpr std::size_t kMaxCases = 100000;
// The largest campaign table, a CSV of at most kMaxCases lines. Unit: [bytes].
constexpr std::size_t kMaxTableBytes = 64u << 20;

std::string Scalar(const YamlInput& in, const YAML::Node& node, const std::string& key_path) {
  if (!node || !node.IsScalar()) {
    in.ThrowValue(node, key_path, "a single value (a number or a word)");
  }
  return node.Scalar();
}

std::vector<std::string> ScalarList(const YamlInput& in, const YAML::Node& node,
                                    const std::string& key_path) {
  if (!node || !node.IsSequence() || node.size() == 0) {
    in.ThrowValue(node, key_path, "a non-empty list of values, e.g. [50, 100, 150]");
  }
  std::vector<std::string> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(Scalar(in, node[i], fmt::format("{}[{}]", key_path, i)));
  }
  return values;
}

std::string Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return std::string(s);
}

// The table's cases: (id or "", params) per line.
std::vector<std::pair<std::string, Params>> ReadTable(const std::string& path,
                                                     const std::string& where) {
  // Regular files only (a FIFO would block for ever), of a bounded size.
  std::istringstream in(ReadInputFile(path, where,
                                      "CSV of cases (a header of key paths, then one case per "
                                      "line)", kMaxTableBytes));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::pair<std::string, Params>> rows;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (Trim(line).empty() || Trim(line)[0] == '#') continue;
    std::vector<std::string> fields;
    for (std::string_view f : io::SplitCsvLine(line)) fields.push_back(Trim(f));
    if (header.empty()) {
      header = fields;
      for (const auto& h : header) {
        if (h.empty()) throw ConfigError(fmt::format("{}:{}: an empty column name", path, line_no));
      }
      continue;
    }
    if (fields.size() != header.size()) {
      throw ConfigError(fmt::format("{}:{}: {} fields where the header has {} columns", path,
                                    line_no, fields.size(), header.size()));
    }
    std::pair<std::string, Params> row;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (header[i] == "id") {
        row.first = fields[i];
      } else {
        row.second.emplace_back(header[i], fields[i]);
      }
    }
    rows.push_back(std::move(row));
    if (rows.size() > kMaxCases) {
      throw ConfigError(fmt::format("{}:{}: more than {} cases in the table; a campaign has at "
                                    "most {} (docs/campaigns.md): split it into several "
                                    "campaigns", path, line_no, kMaxCases, kMaxCases));
    }
  }
  if (rows.empty()) {
    throw ConfigError(fmt::format("{}: no case in the table: add one line per case below the "
                                  "header", path));
  }
  return rows;
}

// The short name of a key path in a case id: the last segment (the whole parameter name).
std::string ShortName(const std::string& key_path) { return SplitKeyPath(key_path).back(); }

std::string Sanitize(const std::string& s) {
  std::string out;
  for (char c : s) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' ||
                    c == '-' || c == '+' || c == '=';
    out += ok ? c : '_';
  }
  return out;
}

bool SameValue(const std::string& a, const std::string& b) {
  if (a == b) return true;
  const auto x = io::ParseCsvNumber(a), y = io::ParseCsvNumber(b);
  return x && y && *x == *y;
}

MetricSpec ParseMetric(const YamlInput& in, const YAML::Node& node, const std::string& where) {
  const std::string text = Scalar(in, node, where);
  static const std::vector<std::pair<std::string, MetricSpec::Kind>> kKinds{
      {"max_abs", MetricSpec::kMaxAbs}, {"max", MetricSpec::kMax}, {"min", MetricSpec::kMin},
      {"rms", MetricSpec::kRms}, {"final", MetricSpec::kFinal}, {"error", MetricSpec::kError}};
  const auto open = text.find('(');
  if (open != std::string::npos && text.back() == ')') {
    const std::string fn = text.substr(0, open);
    const std::string channel = Trim(text.substr(open + 1, text.size() - open - 2));
    for (const auto& [name, kind] : kKinds) {
      if (fn == name && !channel.empty()) return {kind, channel, text};
    }
  }
  in.ThrowValue(node, where, "a metric such as max_abs(q1), max(q1), min(q1), rms(q1), "
                             "final(q1) or error(q1) (against the reference case)");
}

}  // namespace

const char* CaseCommandName(CaseCommand command) {
  switch (command) {
    case CaseCommand::kSimulate: return "simulate";
    case CaseCommand::kRun: return "run";
    case CaseCommand::kPlan: return "plan";
  }
  return "?";
}

std::vector<std::string> SplitKeyPath(const std::string& key_path) {
  std::vector<std::string> parts;
  std::string current;
  for (std::size_t i = 0; i < key_path.size(); ++i) {
    if (key_path[i] == '.' && !(parts.size() > 0 && parts.back() == "parameters")) {
      parts.push_back(current);
      current.clear();
    } else if (!parts.empty() && parts.back() == "parameters") {
      current = key_path.substr(i);
      break;
    } else {
      current += key_path[i];
    }
  }
  parts.push_back(current);
  for (const auto& p : parts) {
    if (p.empty()) {
      throw ConfigError(fmt::format("key path '{}': an empty segment; write keys joined by "
                                    "dots, e.g. model.parameters.f_w", key_path));
    }
  }
  return parts;
}

void SetKeyPath(YAML::Node root, const std::string& key_path, const std::string& value) {
  const auto parts = SplitKeyPath(key_path);
  YAML::Node node = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (child && !child.IsMap() && !child.IsNull()) {
      throw ConfigError(fmt::format("key path '{}': '{}' is a value in the base config, not a "
                                    "section; vary a key inside a section", key_path, parts[i]));
    }
    if (!child || child.IsNull()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
    }
    node.reset(node[parts[i]]);
  }
  node[parts.back()] = value;
}

bool IsValidCaseId(const std::string& id) {
  return !id.empty() && id.size() <= 120 && id[0] != '.' && Sanitize(id) == id;
}

Campaign LoadCampaign(const std::string& path) {
  const YamlInput in = YamlInput::FromFile(path, "keys such as base:, command:, grid:");
  const YAML::Node& root = in.root();
  in.CheckKeys(root, "", {"base", "command", "set", "grid", "table", "seeds", "metrics",
                          "reference", "plan", "figures"});
  Campaign c;
  c.path = path;
  c.text = in.text();
  const fs::path dir = fs::path(path).parent_path();
  auto resolve = [&](const std::string& p) {
    return fs::path(p).is_relative() ? (dir / p).lexically_normal().string() : p;
  };
  c.base_path = resolve(Scalar(in, root["base"], "base"));
  {
    const YamlInput base = YamlInput::FromFile(c.base_path, "keys such as model:, integrator:");
    c.base_text = base.text();
  }
  const std::string command = in.ReadString(root, "", "command", "simulate");
  if (command == "simulate") c.command = CaseCommand::kSimulate;
  else if (command == "run") c.command = CaseCommand::kRun;
  else if (command == "plan") c.command = CaseCommand::kPlan;
  else in.ThrowValue(root["command"], "command", "simulate, run or plan");

  if (const YAML::Node set = in.Mapping(root, "set", "set", false)) {
    for (const auto& kv : set) {
      const std::string key = kv.first.Scalar();
      c.set.emplace_back(key, Scalar(in, kv.second, "set." + key));
    }
  }
  // The product table × grid × seeds.
  std::vector<std::pair<std::string, Params>> cases{{"", {}}};
  bool named = false;
  if (root["table"]) {
    cases = ReadTable(resolve(Scalar(in, root["table"], "table")), in.Where(root["table"], "table"));
    named = !cases.front().first.empty();
  }
  // `where` names the key that multiplies the cases, for the message when there are too many.
  auto multiply = [&](const std::string& key, const std::vector<std::string>& values,
                      const std::string& where) {
    if (cases.size() * values.size() > kMaxCases) {  // each at most 10⁵: no overflow
      throw ConfigError(fmt::format(
          "{}: {} values make {} × {} = {} cases; a campaign has at most {} (docs/campaigns.md): "
          "use fewer values, or split the campaign", where, values.size(), cases.size(),
          values.size(), cases.size() * values.size(), kMaxCases));
    }
    std::vector<std::pair<std::string, Params>> next;
    next.reserve(cases.size() * values.size());
    for (const auto& row : cases) {
      for (const auto& v : values) {
        auto r = row;
        r.second.emplace_back(key, v);
        if (!r.first.empty()) r.first += fmt::format("-{}={}", ShortName(key), Sanitize(v));
        next.push_back(std::move(r));
      }
    }
    cases = std::move(next);
  };
  if (const YAML::Node grid = in.Mapping(root, "grid", "grid", false)) {
    for (const auto& kv : grid) {
      const std::string key = kv.first.Scalar();
      multiply(key, ScalarList(in, kv.second, "grid." + key), in.Where(kv.second, "grid." + key));
    }
  }
  if (const YAML::Node seeds = in.Mapping(root, "seeds", "seeds", false)) {
    in.CheckKeys(seeds, "seeds", {"key", "values", "count", "first"});
    const std::string key = Scalar(in, seeds["key"], "seeds.key");
    std::vector<std::string> values;
    if (seeds["values"]) {
      values = ScalarList(in, seeds["values"], "seeds.values");
    } else {
      const long long count = in.Count(seeds["count"], "seeds.count", "a number of seeds", 1,
                                       static_cast<long long>(kMaxCases));
      const long long first = seeds["first"] ? in.Count(seeds["first"], "seeds.first",
                                                        "the first seed", 0, 1LL << 53) : 1;
      for (long long s = 0; s < count; ++s) values.push_back(std::to_string(first + s));
    }
    multiply(key, values,
             in.Where(seeds["values"] ? seeds["values"] : seeds["count"],
                      seeds["values"] ? "seeds.values" : "seeds.count"));
  }
  if (cases.size() == 1 && cases.front().second.empty()) {
    in.ThrowValue(root["grid"], "grid", "variations: grid:, table: or seeds: (at least one)");
  }
  for (const auto& [key, value] : cases.front().second) c.varied.push_back(key);
  const int width = static_cast<int>(std::to_string(cases.size() - 1).size());
  std::set<std::string> ids;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    CaseSpec cs;
    cs.params = cases[i].second;
    if (named) {
      cs.id = cases[i].first;
    } else {
      cs.id = fmt::format("c{:0{}}", i, width);
      for (const auto& [key, value] : cs.params) {
        cs.id += fmt::format("-{}={}", ShortName(key), Sanitize(value));
      }
      if (cs.id.size() > 120) cs.id = fmt::format("c{:0{}}", i, width);
    }
    for (const auto& [key, value] : cs.params) SplitKeyPath(key);  // checks the path
    if (!IsValidCaseId(cs.id)) {
      throw ConfigError(fmt::format("{}: case id '{}': use letters, digits and . _ = + - only "
                                    "(at most 120, not starting with a dot)", path, cs.id));
    }
    if (!ids.insert(cs.id).second) {
      throw ConfigError(fmt::format("{}: two cases have the id '{}': every case needs its own "
                                    "(remove the repeated line or value)", path, cs.id));
    }
    c.cases.push_back(std::move(cs));
  }
  if (const YAML::Node metrics = root["metrics"]) {
    if (!metrics.IsSequence()) in.ThrowValue(metrics, "metrics", "a list, e.g. [max_abs(q1)]");
    for (std::size_t i = 0; i < metrics.size(); ++i) {
      c.metrics.push_back(ParseMetric(in, metrics[i], fmt::format("metrics[{}]", i)));
    }
  }
  if (const YAML::Node ref = root["reference"]) {
    for (std::size_t i = 0; i < c.cases.size() && c.reference < 0; ++i) {
      bool match = true;
      if (ref.IsScalar()) {
        match = c.cases[i].id == ref.Scalar();
      } else if (ref.IsMap()) {
        for (const auto& kv : ref) {
          bool found = false;
          for (const auto& [key, value] : c.cases[i].params) {
            found = found || (key == kv.first.Scalar() && SameValue(value, kv.second.Scalar()));
          }
          match = match && found;
        }
      }
      if (match) c.reference = static_cast<int>(i);
    }
    if (c.reference < 0) {
      in.ThrowValue(ref, "reference", "a case id, or the varied values of one case, e.g. "
                                      "{model.parameters.f_w: 100}");
    }
  }
  for (const auto& m : c.metrics) {
    if (m.kind == MetricSpec::kError && c.reference < 0) {
      in.ThrowValue(root["reference"], "reference",
                    fmt::format("the case {} compares against (reference:)", m.name));
    }
  }
  if (const YAML::Node plan = in.Mapping(root, "plan", "plan", false)) {
    in.CheckKeys(plan, "plan", {"tolerance", "emulate"});
    c.plan_tolerance = in.ReadNumber(plan, "plan", "tolerance", "a positive relative error", 0.01);
    if (!(c.plan_tolerance > 0)) {
      in.ThrowValue(plan["tolerance"], "plan.tolerance", "a positive relative error, e.g. 0.01");
    }
    if (plan["emulate"]) c.plan_emulate = resolve(Scalar(in, plan["emulate"], "plan.emulate"));
  }
  if (root["figures"]) {
    const std::string f = Scalar(in, root["figures"], "figures");
    if (f != "true" && f != "false") in.ThrowValue(root["figures"], "figures", "true or false");
    c.figures = f == "true";
  }
  return c;
}

namespace {

// A key under substructures.SLOT.transfer.bench. of a slot whose bench is a file: the file's
// `bench:` mapping is copied inline (in place of `config:`) so that the key can be set.
void InlineBenchFor(YAML::Node root, const std::string& key_path, const fs::path& base_dir) {
  const auto parts = SplitKeyPath(key_path);
  if (parts.size() < 5 || parts[0] != "substructures" || parts[2] != "transfer" ||
      parts[3] != "bench") {
    return;
  }
  YAML::Node transfer = root["substructures"][parts[1]]["transfer"];
  if (!transfer || !transfer.IsMap() || transfer["bench"] || !transfer["config"] ||
      !transfer["config"].IsScalar()) {
    return;
  }
  fs::path file = transfer["config"].Scalar();
  if (file.is_relative()) file = base_dir / file;
  const YamlInput bench = YamlInput::FromFile(file.string(), "a `bench:` mapping");
  if (!bench.root()["bench"] || !bench.root()["bench"].IsMap()) {
    throw ConfigError(fmt::format("key path '{}': the bench file {} has no `bench:` mapping to "
                                  "vary", key_path, file.string()));
  }
  transfer["bench"] = YAML::Clone(bench.root()["bench"]);
  transfer.remove("config");
}

}  // namespace

std::string CaseConfigText(const Campaign& campaign, int index, const std::string& case_dir) {
  YAML::Node root = YAML::Load(campaign.base_text);
  const fs::path base_parent = fs::path(campaign.base_path).parent_path();
  for (const auto& [key, value] : campaign.set) InlineBenchFor(root, key, base_parent);
  for (const auto& [key, value] : campaign.cases.at(index).params) {
    InlineBenchFor(root, key, base_parent);
  }
  for (const auto& [key, value] : campaign.set) SetKeyPath(root, key, value);
  for (const auto& [key, value] : campaign.cases.at(index).params) SetKeyPath(root, key, value);
  if (root["output"] && root["output"].IsMap()) root["output"].remove("csv");
  if (root["output"] && root["output"].IsMap() && root["output"].size() == 0) root.remove("output");
  // The files the base names, relative to its folder, now relative to the case's folder.
  const fs::path base_dir = fs::absolute(fs::path(campaign.base_path).parent_path());
  const fs::path to = fs::absolute(case_dir);
  auto rebase = [&](YAML::Node node) {
    if (!node || !node.IsScalar()) return;
    const fs::path p = node.Scalar();
    if (p.is_absolute()) return;
    node = (base_dir / p).lexically_normal().lexically_relative(to.lexically_normal()).string();
  };
  if (root["model"] && root["model"].IsMap()) rebase(root["model"]["file"]);
  if (root["substructures"] && root["substructures"].IsMap()) {
    for (auto slot : root["substructures"]) {
      const YAML::Node transfer = slot.second.IsMap() ? slot.second["transfer"] : YAML::Node();
      if (!transfer || !transfer.IsMap()) continue;
      rebase(slot.second["transfer"]["config"]);
      rebase(slot.second["transfer"]["token_file"]);
    }
  }
  YAML::Emitter out;
  out << root;
  std::ostringstream text;
  text << "# Case " << campaign.cases.at(index).id << " of the campaign " << campaign.path
       << " (base " << campaign.base_path << ")\n" << out.c_str() << "\n";
  return text.str();
}

}  // namespace hybridtest::campaign
