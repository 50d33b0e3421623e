// Model files: time functions, restoring-force slots, forces and torques. See model_file.h and
// docs/model-files.md.
#include <fmt/core.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/modelfile/compiled_scalar.h"
#include "hybridtest/modelfile/file_context.h"
#include "hybridtest/modelfile/names.h"

namespace hybridtest::modelfile::internal {

namespace {
// Declares a name for expressions, refusing one already taken.
void Declare(FileContext& c, Symbol s, const std::string& where) {
  if (s.name == "t" || s.name == "pi" || c.symbols.Find(s.name) != nullptr) {
    throw ConfigError(fmt::format("{}: the name '{}' is already used; rename it", where, s.name));
  }
  c.symbols.Add(std::move(s));
}

// Whether the sub-tree at i reads a slot r_k, and whether it is linear in the slots (the
// engine's coupling matrix ∂g/∂r relies on g being affine in r).
struct SlotUse {
  bool uses = false;
  bool linear = true;
};
SlotUse SlotUsage(const std::vector<Node>& nodes, int i) {
  const Node& n = nodes[i];
  if (n.op == Op::kSlot) return {true, true};
  if (n.a < 0) return {false, true};
  const SlotUse a = SlotUsage(nodes, n.a);
  SlotUse b = n.b >= 0 ? SlotUsage(nodes, n.b) : SlotUse{};
  if (n.c >= 0) {
    // if(cond, x, y): linear in the slots only if no operand reads one.
    const SlotUse c3 = SlotUsage(nodes, n.c);
    b = {b.uses || c3.uses, b.linear && c3.linear};
  }
  const bool both_linear = a.linear && b.linear;
  switch (n.op) {
    case Op::kNeg: case Op::kAdd: case Op::kSub:
      return {a.uses || b.uses, both_linear};
    case Op::kMul: return {a.uses || b.uses, both_linear && !(a.uses && b.uses)};
    case Op::kDiv: return {a.uses || b.uses, both_linear && !b.uses};
    default: return {a.uses || b.uses, !(a.uses || b.uses)};
  }
}
}  // namespace

namespace {
// The numbers of a CSV file next to the model file: one vector per line that has any (a first
// line that is not numbers is a header and skipped; `#` starts a comment). Throws ConfigError
// naming file:line.
std::vector<std::vector<double>> ReadCsv(const FileContext& c, const YAML::Node& node,
                                         const std::string& kp, bool grid) {
  const std::string name = c.in.String(node, kp, "a CSV file next to the model file");
  const std::filesystem::path path =
      std::filesystem::path(c.in.path()).parent_path() / std::filesystem::path(name);
  RequireRegularFile(path.string(), c.Where(node, kp), "CSV file next to the model file");
  std::ifstream file(path);
  if (!file) {
    throw ConfigError(fmt::format("{} = '{}': cannot read {}; give a CSV file next to the model "
                                  "file", c.Where(node, kp), name, path.string()));
  }
  if (c.tables_read != nullptr) c.tables_read->push_back(path.lexically_normal().string());
  std::vector<std::vector<double>> rows;
  std::string line;
  std::size_t bytes = 0;
  for (int number = 1; std::getline(file, line); ++number) {
    bytes += line.size() + 1;
    if (bytes > kMaxConfigBytes) {
      throw ConfigError(fmt::format("{}: larger than {} bytes", path.string(), kMaxConfigBytes));
    }
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r,;") == std::string::npos) continue;
    std::vector<double> row;
    bool numbers = true;
    std::size_t start = 0;
    for (std::size_t cell = 0;; ++cell) {
      const std::size_t end = line.find_first_of(",;\t", start);
      std::string text = line.substr(start, end == std::string::npos ? std::string::npos : end - start);
      text.erase(0, text.find_first_not_of(" \r"));
      text.erase(text.find_last_not_of(" \r") + 1);
      char* stop = nullptr;
      const double v = std::strtod(text.c_str(), &stop);
      if (grid && rows.empty() && cell == 0) {
        row.push_back(0.0);  // the grid's corner cell: a label or nothing
      } else if (text.empty() || *stop != '\0' || !std::isfinite(v)) {
        numbers = false;
        row.push_back(0.0);
      } else {
        row.push_back(v);
      }
      if (end == std::string::npos) break;
      start = end + 1;
    }
    if (!numbers) {
      if (rows.empty() && !grid) continue;  // a header line
      throw ConfigError(fmt::format("{}:{}: '{}' is not a row of numbers; a {} has {}",
                                    path.string(), number, line, grid ? "grid CSV" : "CSV table",
                                    grid ? "a first row of y values after a corner cell, then "
                                           "rows of x followed by its z values"
                                         : "rows of x, y"));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}
}  // namespace

void ReadTables(FileContext& c, const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return;
  c.in.RequireMapping(node, "tables");
  for (const auto& kv : node) {
    const std::string name = kv.first.as<std::string>();
    const std::string kp = "tables." + name;
    const std::string where = c.Where(kv.first, kp);
    CheckName(c.in, kv.first, kp, name);
    if (IsFunctionName(name)) {
      throw ConfigError(fmt::format("{}: '{}' is a built-in function; give the table another "
                                    "name", where, name));
    }
    c.in.RequireMapping(kv.second, kp);
    c.in.CheckKeys(kv.second, kp, {"x", "y", "z", "csv", "csv_grid", "description"});
    Table table;
    const bool csv = kv.second["csv"].IsDefined(), csv_grid = kv.second["csv_grid"].IsDefined();
    if (csv || csv_grid) {
      if (csv && csv_grid) {
        throw ConfigError(fmt::format("{}: give `csv` (rows of x, y) or `csv_grid` (a grid z(x, "
                                      "y)), not both", c.Where(kv.second, kp)));
      }
      const std::string key = csv ? "csv" : "csv_grid";
      const auto rows = ReadCsv(c, kv.second[key], kp + "." + key, csv_grid);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::size_t want = csv ? 2 : rows.front().size();
        if (rows[i].size() != want) {
          throw ConfigError(fmt::format("{}: row {} of the numbers has {} values, expected {}",
                                        c.Where(kv.second[key], kp + "." + key), i + 1,
                                        rows[i].size(), want));
        }
        if (csv) {
          table.x.push_back(rows[i][0]);
          table.y.push_back(rows[i][1]);
        } else if (i == 0) {
          table.y.assign(rows[i].begin() + 1, rows[i].end());
        } else {
          table.x.push_back(rows[i][0]);
          table.z.insert(table.z.end(), rows[i].begin() + 1, rows[i].end());
        }
      }
    }
    const std::vector<std::string> inline_axes =
        csv || csv_grid ? std::vector<std::string>{} : std::vector<std::string>{"x", "y"};
    for (const std::string& axis_name : inline_axes) {
      const char* axis = axis_name.c_str();
      const YAML::Node list = c.Require(kv.second, axis, kp, "a list of numbers [a, b, ...]");
      if (!list.IsSequence()) c.in.ThrowValue(list, kp + "." + axis, "a list of numbers [a, b, ...]");
      std::vector<double>& out = std::string(axis) == "x" ? table.x : table.y;
      for (std::size_t i = 0; i < list.size(); ++i) {
        out.push_back(c.Constant(list[i], fmt::format("{}.{}[{}]", kp, axis, i),
                                 "a number (numbers, units and parameters)"));
      }
    }
    const bool two_d = kv.second["z"].IsDefined() || csv_grid;
    if (two_d && !csv_grid) {
      // z(x, y): one row per x, one entry per y.
      const YAML::Node rows = kv.second["z"];
      if (!rows.IsSequence() || rows.size() != table.x.size()) {
        c.in.ThrowValue(rows, kp + ".z", fmt::format("{} rows (one per x) of {} values (one per y)",
                                                     table.x.size(), table.y.size()));
      }
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::string row = fmt::format("{}.z[{}]", kp, i);
        if (!rows[i].IsSequence() || rows[i].size() != table.y.size()) {
          c.in.ThrowValue(rows[i], row, fmt::format("a row of {} values (one per y)", table.y.size()));
        }
        for (std::size_t j = 0; j < rows[i].size(); ++j) {
          table.z.push_back(c.Constant(rows[i][j], fmt::format("{}[{}]", row, j), "a number"));
        }
      }
    }
    if (table.x.size() < 2 || (two_d ? table.y.size() < 2 : table.x.size() != table.y.size())) {
      throw ConfigError(fmt::format("{}: {} x and {} y values; give at least two points and {}",
                                    c.Where(kv.second, kp), table.x.size(), table.y.size(),
                                    two_d ? "at least two y" : "as many y as x"));
    }
    for (const char* axis : {"x", "y"}) {
      const std::vector<double>& g = std::string(axis) == "x" ? table.x : table.y;
      if (std::string(axis) == "y" && !two_d) break;
      for (std::size_t i = 1; i < g.size(); ++i) {
        if (!(g[i] > g[i - 1])) {
          const std::string at = csv || csv_grid
                                        ? c.Where(kv.second, kp)
                                        : c.Where(kv.second[axis][i], fmt::format("{}.{}[{}]", kp, axis, i));
          throw ConfigError(fmt::format("{}: {} must increase strictly; {}[{}] = {:g} follows {:g}",
                                        at, axis, axis, i, g[i], g[i - 1]));
        }
      }
    }
    if (c.symbols.Find(name) != nullptr) {
      throw ConfigError(fmt::format("{}: the name '{}' is already used; rename it", where, name));
    }
    c.symbols.AddTable(name, std::move(table));
  }
}

void ReadTimeFunctions(FileContext& c, const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return;
  c.in.RequireMapping(node, "time_functions");
  for (const auto& kv : node) {
    const std::string name = kv.first.as<std::string>();
    const std::string kp = "time_functions." + name;
    CheckName(c.in, kv.first, kp, name);
    auto e = std::make_shared<const CompiledScalar>(c.Parse(kv.second, kp));
    if (e->expression.Uses(Op::kCoordinate) || e->expression.Uses(Op::kSpeed) ||
        e->expression.Uses(Op::kSlot) || e->expression.Uses(Op::kTimeFunction) ||
        e->expression.Uses(Op::kState)) {
      throw ConfigError(fmt::format("{} = '{}': a time function may use only t and parameters",
                                    c.Where(kv.second, kp), kv.second.Scalar()));
    }
    const int index = c.builder->AddTimeFunction(name, [e](const auto& t) {
      using T = std::decay_t<decltype(t)>;
      const Variables<T> v{t, {}, {}, {}, {}};
      return e->Eval(v);
    });
    Declare(c, {name, Op::kTimeFunction, index, 0.0, e->expression.dim()}, c.Where(kv.first, kp));
  }
}

std::vector<double> ReadSlots(FileContext& c, const YAML::Node& node) {
  std::vector<double> stiffness;
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = ListItems(c.in, node, "slots", &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const YAML::Node& s = items[i];
    const std::string& kp = labels[i];
    c.in.RequireMapping(s, kp);
    c.in.CheckKeys(s, kp, {"name", "unit", "description", "displacement", "stiffness"});
    const std::string name = c.in.String(s["name"], kp + ".name", "a slot name such as r1");
    CheckName(c.in, s["name"], kp + ".name", name);
    std::string unit = c.in.ReadString(s, kp, "unit", "N");
    if (unit == "N*m" || unit == "Nm" || unit == "N m" || unit == "N.m") unit = "N·m";
    if (unit != "N" && unit != "N·m") {
      c.in.ThrowValue(s["unit"], kp + ".unit", "N (a force, displacement in m) or N·m (a "
                                               "moment, displacement in rad)");
    }
    multibody::ScalarField d =
        c.Field(s["displacement"], kp + ".displacement", unit == "N" ? kLength : kDimensionless);
    // Required: a forgotten stiffness must not silently remove the default numerical spring.
    const std::string expected = unit == "N" ? "a stiffness in N/m" : "a stiffness in N·m/rad";
    stiffness.push_back(c.Constant(
        c.Require(s, "stiffness", kp, expected + " for the default numerical substructure "
                                      "(write `stiffness: 0` for none)"),
        kp + ".stiffness", expected, unit == "N" ? Dim{true, {0, 1, -2}} : kMoment));
    try {
      const int index = c.builder->AddRestoringForceSlot(
          name, c.in.ReadString(s, kp, "description", ""), std::move(d), unit);
      Declare(c, {name, Op::kSlot, index, 0.0, unit == "N" ? kForce : kMoment},
              c.Where(s["name"], kp + ".name"));
    } catch (const ModelError& e) {
      throw ConfigError(fmt::format("{}: {}", c.Where(s, kp), e.what()));
    }
  }
  return stiffness;
}

namespace {
void ReadLoadList(FileContext& c, const YAML::Node& node, const std::string& key, bool force) {
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = ListItems(c.in, node, key, &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const YAML::Node& l = items[i];
    const std::string& kp = labels[i];
    c.in.RequireMapping(l, kp);
    if (force) {
      c.in.CheckKeys(l, kp, {"name", "point", "expressed_in", "value"});
    } else {
      c.in.CheckKeys(l, kp, {"name", "frame", "expressed_in", "value"});
    }
    const std::string name = c.in.String(l["name"], kp + ".name", "a name");
    CheckName(c.in, l["name"], kp + ".name", name, NameKind::kText);
    const multibody::FrameId in =
        l["expressed_in"] ? c.Frame(l["expressed_in"], kp + ".expressed_in") : multibody::FrameId{0};
    const std::string expected = fmt::format("three components [x, y, z] in `expressed_in`, in {}",
                                             force ? "N" : "N·m");
    const YAML::Node value = c.Require(l, "value", kp, expected);
    c.RequireVector3(value, kp + ".value", expected);
    std::vector<CompiledScalar> parts;
    for (int k = 0; k < 3; ++k) {
      const std::string vkp = fmt::format("{}.value[{}]", kp, k);
      Expression e = c.Parse(value[k], vkp);
      if (!SlotUsage(e.nodes(), e.root()).linear) {
        throw ConfigError(fmt::format("{} = '{}': not linear in the slots r (a slot may be added "
                                      "or multiplied by something free of slots, not passed "
                                      "through a function); the hybrid coupling needs loads "
                                      "affine in r", c.Where(value[k], vkp), value[k].Scalar()));
      }
      c.CheckDim(value[k], vkp, e, force ? kForce : kMoment);
      parts.emplace_back(std::move(e));
    }
    auto load = std::make_shared<const std::vector<CompiledScalar>>(std::move(parts));
    auto f = [load](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      const Variables<T> v{a.t, a.q, a.u, a.r, a.time_values, a.z};
      return multibody::Vector3<T>((*load)[0].Eval(v), (*load)[1].Eval(v), (*load)[2].Eval(v));
    };
    try {
      if (force) {
        c.builder->AddForce(name, c.Point(l["point"], kp + ".point"), in, f);
      } else {
        c.builder->AddTorque(name, c.Frame(l["frame"], kp + ".frame"), in, f);
      }
    } catch (const ModelError& e) {
      throw ConfigError(fmt::format("{}: {}", c.Where(l, kp), e.what()));
    }
  }
}
}  // namespace

void ReadLoads(FileContext& c, const YAML::Node& forces, const YAML::Node& torques) {
  ReadLoadList(c, forces, "forces", true);
  ReadLoadList(c, torques, "torques", false);
}

}  // namespace hybridtest::modelfile::internal
