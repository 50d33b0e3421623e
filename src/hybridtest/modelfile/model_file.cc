// Model files: top level, parameters, coordinates and the expression helpers. See
// model_file.h.
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/modelfile/model_file_modes.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/compiled_scalar.h"
#include "hybridtest/modelfile/file_context.h"
#include "hybridtest/modelfile/names.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile {

namespace {
// A coordinate's or speed's unit: the engine's state is SI, so only SI units are accepted (a
// coordinate in m, rad or 1; its speed per second); a lab unit is refused with the fix.
void CheckStateUnit(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                    const std::string& text, bool coordinate) {
  std::string why;
  const std::optional<Unit> unit = ParseUnit(text, &why);
  if (!unit) throw ConfigError(fmt::format("{} = '{}': {}", in.Where(node, kp), text, why));
  const auto& d = unit->dim;
  const bool length = d == std::array<int, 4>{1, 0, 0, 0};
  const bool angle = d == std::array<int, 4>{0, 0, 0, 1};
  const bool plain = d == std::array<int, 4>{0, 0, 0, 0};
  const int s = coordinate ? 0 : -1;
  const bool kind_ok = coordinate ? (length || angle || plain)
                                  : (d[0] + d[3] <= 1 && d[1] == 0 && d[2] == s);
  if (unit->to_si != 1.0) {
    throw ConfigError(fmt::format(
        "{} = '{}': the engine's state is in SI, so a {} is in {} ({:g} {} = 1 {}); write "
        "`unit: {}` and give initial conditions in SI. Parameters may keep lab units: "
        "`L: {{value: 600, unit: mm}}` is read as 0.6 m", in.Where(node, kp), text,
        coordinate ? "coordinate" : "speed", coordinate ? "m or rad" : "m/s or rad/s",
        1.0 / unit->to_si, text, unit->si, unit->si));
  }
  if (!kind_ok) {
    throw ConfigError(fmt::format("{} = '{}': a {} is {}; write one of those", in.Where(node, kp),
                                  text, coordinate ? "coordinate" : "speed",
                                  coordinate ? "a length (m), an angle (rad) or a number (1)"
                                             : "a rate per second (m/s, rad/s or 1/s)"));
  }
}

// Quantities (coordinates or speeds) as a list of {name, unit, description}.
std::vector<multibody::QuantityInfo> ReadQuantities(const YamlInput& in, const YAML::Node& root,
                                                    const std::string& key) {
  std::vector<multibody::QuantityInfo> out;
  std::vector<std::string> labels;
  const std::vector<YAML::Node> items = internal::ListItems(in, root[key], key, &labels);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string& kp = labels[i];
    in.RequireMapping(items[i], kp);
    in.CheckKeys(items[i], kp, {"name", "unit", "description", "initial"});
    const std::string unit = in.String(items[i]["unit"], kp + ".unit",
                                       key == "coordinates" ? "m or rad" : "m/s or rad/s");
    CheckStateUnit(in, items[i]["unit"], kp + ".unit", unit, key == "coordinates");
    const std::string name = in.String(items[i]["name"], kp + ".name", "a name such as q1 or theta");
    CheckName(in, items[i]["name"], kp + ".name", name);
    out.push_back({name, unit, in.ReadString(items[i], kp, "description", "")});
  }
  return out;
}
}  // namespace

ModelFile ParseModelFile(YamlInput input) {
  ModelFile f{std::move(input), {}, {}, {}};
  const YamlInput& in = f.input;
  const YAML::Node& root = in.root();
  in.CheckKeys(root, "", {"name", "description", "parameters", "coordinates", "speeds",
                          "kinematical_equations", "tables", "time_functions", "frames", "points",
                          "particles", "bodies", "slots", "states", "forces", "torques",
                          "constraints", "dependent_speeds", "dependent_coordinates",
                          "constraint_stabilisation", "modes"});
  ReadModeReading(in);  // checked on load; used by the modes analysis
  f.name = in.ReadString(root, "", "name",
                         LabelFromStem(std::filesystem::path(in.path()).stem().string()));
  if (root["name"]) CheckName(in, root["name"], "name", f.name, NameKind::kLabel);
  f.description = in.ReadString(root, "", "description", "model file " + in.path());
  const YAML::Node params = in.Mapping(root, "parameters", "parameters", false);
  if (params.IsDefined()) {
    for (const auto& kv : params) {
      const std::string name = kv.first.as<std::string>();
      const std::string kp = "parameters." + name;
      CheckName(in, kv.first, kp, name);
      if (kv.second.IsScalar()) {
        f.parameters.Add(name, in.Number(kv.second, kp, "a number in SI units"), "", "");
        continue;
      }
      in.RequireMapping(kv.second, kp);
      in.CheckKeys(kv.second, kp, {"value", "unit", "description"});
      const double value = in.ReadNumber(kv.second, kp, "value", "a number in its `unit`");
      const std::string unit_text = in.ReadString(kv.second, kp, "unit", "");
      std::string description = in.ReadString(kv.second, kp, "description", "");
      if (unit_text.empty()) {
        f.parameters.Add(name, value, "", description);
        continue;
      }
      // Converted to SI here, once: the engine and the run config's overrides are SI.
      std::string why;
      const std::optional<Unit> unit = ParseUnit(unit_text, &why);
      if (!unit) {
        throw ConfigError(fmt::format("{} = '{}': {}; or leave `unit:` out and give the value "
                                      "in SI", in.Where(kv.second["unit"], kp + ".unit"),
                                      unit_text, why));
      }
      if (unit->to_si != 1.0) {
        description += fmt::format("{}(given as {:g} {})", description.empty() ? "" : " ", value,
                                   unit_text);
      }
      f.parameters.Add(name, value * unit->to_si, unit->to_si == 1.0 ? unit_text : unit->si,
                       description);
    }
  }
  return f;
}

ModelFile LoadModelFile(const std::string& path) {
  return ParseModelFile(YamlInput::FromFile(
      path, "keys such as name:, parameters:, coordinates:, frames:, points:, particles:"));
}

models::BuiltModel BuildModelFile(const ModelFile& file, const models::ParameterSet& parameters,
                                  std::vector<std::string>* tables_read) {
  const YamlInput& in = file.input;
  const YAML::Node& root = in.root();
  std::vector<multibody::QuantityInfo> coordinates = ReadQuantities(in, root, "coordinates");
  std::vector<multibody::QuantityInfo> speeds = ReadQuantities(in, root, "speeds");
  if (coordinates.empty()) {
    throw ConfigError(fmt::format("{}: no coordinates; add `coordinates:` with at least one "
                                  "{{name, unit, description}}", in.Where(root, "coordinates")));
  }
  if (!speeds.empty() && speeds.size() != coordinates.size()) {
    throw ConfigError(fmt::format("{}: {} speeds for {} coordinates; list one speed per "
                                  "coordinate, or none (then u_k = q̇_k)",
                                  in.Where(root["speeds"], "speeds"), speeds.size(),
                                  coordinates.size()));
  }
  internal::FileContext c{in, {}, {}, {}, nullptr, static_cast<int>(coordinates.size()), {}, {}};
  c.tables_read = tables_read;
  for (const YAML::Node& s : internal::ListItems(in, root["slots"], "slots")) {
    if (s.IsMap() && s["name"] && s["name"].IsScalar()) c.slot_names.push_back(s["name"].Scalar());
  }
  // Names: t, coordinates, speeds, parameters; each declared once.
  std::set<std::string> seen{"t", "pi", "N", "O"};
  auto declare = [&](const std::string& name, Op kind, int index, double value,
                     const std::string& where, const std::string& unit) {
    if (!seen.insert(name).second) {
      throw ConfigError(fmt::format("{}: the name '{}' is already used (t, pi, N and O are "
                                    "reserved); rename it", where, name));
    }
    c.symbols.Add({name, kind, index, value, Dim::OfUnit(unit)});
  };
  c.symbols.Add({"t", Op::kTime, -1, 0.0, Dim{true, {0, 0, 1}}});
  // The places of the names (after `repeat:` expansion: the copy's line and label).
  std::vector<std::string> coordinate_labels, speed_labels;
  const std::vector<YAML::Node> coordinate_items =
      internal::ListItems(in, root["coordinates"], "coordinates", &coordinate_labels);
  const std::vector<YAML::Node> speed_items =
      internal::ListItems(in, root["speeds"], "speeds", &speed_labels);
  for (std::size_t k = 0; k < coordinates.size(); ++k) {
    declare(coordinates[k].name, Op::kCoordinate, static_cast<int>(k), 0.0,
            in.Where(coordinate_items[k]["name"], coordinate_labels[k] + ".name"),
            coordinates[k].unit);
  }
  for (std::size_t k = 0; k < speeds.size(); ++k) {
    declare(speeds[k].name, Op::kSpeed, static_cast<int>(k), 0.0,
            in.Where(speed_items[k]["name"], speed_labels[k] + ".name"), speeds[k].unit);
  }
  if (speeds.empty()) {
    for (std::size_t k = 0; k < coordinates.size(); ++k) {
      const std::string name = fmt::format("u{}", k + 1);
      speeds.push_back({name, coordinates[k].unit + "/s",
                        "time derivative of " + coordinates[k].name});
      declare(name, Op::kSpeed, static_cast<int>(k), 0.0, in.Where(root, "speeds"),
              speeds.back().unit);
    }
  }
  for (const models::Parameter& p : parameters.all()) {
    declare(p.name, Op::kConst, -1, p.value, in.Where(root["parameters"], "parameters." + p.name),
            p.unit);
  }
  // Extra states: named now (so that an angle that reads one is told where states go), their
  // rates read after the slots (a rate may use velocity()).
  const YAML::Node states = in.Mapping(root, "states", "states", false);
  if (states.IsDefined()) {
    int k = 0;
    for (const auto& kv : states) {
      const std::string name = kv.first.as<std::string>();
      CheckName(in, kv.first, "states." + name, name);
      const YAML::Node unit = kv.second.IsMap() ? kv.second["unit"] : YAML::Node();
      declare(name, Op::kState, k++, 0.0, in.Where(kv.first, "states." + name),
              unit.IsDefined() && unit.IsScalar() ? unit.Scalar() : "1");
    }
  }

  try {
    multibody::ModelBuilder builder(coordinates, speeds);
    c.builder = &builder;
    c.frames["N"] = builder.newtonian();
    c.points["O"] = builder.origin();
    c.mirror->num_coordinates = c.num_coordinates;
    c.mirror->frames.emplace_back();
    c.mirror->points.emplace_back();
    c.mirror->frame_ids["N"] = 0;
    c.mirror->point_ids["O"] = 0;
    internal::ReadTables(c, root["tables"]);
    internal::ReadKinematicalEquations(c, root["kinematical_equations"]);
    internal::ReadTimeFunctions(c, root["time_functions"]);
    internal::ReadFrames(c, root["frames"]);
    internal::ReadPoints(c, root["points"]);
    internal::ReadMasses(c, root["particles"], root["bodies"]);
    std::vector<double> stiffness = internal::ReadSlots(c, root["slots"]);
    c.symbols.SetMirror(c.mirror);  // velocity() and angular_velocity(): loads only
    internal::ReadExtraStates(c, states);
    internal::ReadLoads(c, root["forces"], root["torques"]);
    // Initial values (constants of the parameters), then the constraints.
    std::vector<double> q0(coordinates.size(), 0.0), u0(coordinates.size(), 0.0);
    for (std::size_t k = 0; k < coordinate_items.size() && k < q0.size(); ++k) {
      if (!coordinate_items[k]["initial"]) continue;
      q0[k] = c.Constant(coordinate_items[k]["initial"], coordinate_labels[k] + ".initial",
                         "the coordinate's initial value in SI (a constant)");
    }
    for (std::size_t k = 0; k < speed_items.size() && k < u0.size(); ++k) {
      if (!speed_items[k]["initial"]) continue;
      u0[k] = c.Constant(speed_items[k]["initial"], speed_labels[k] + ".initial",
                         "the speed's initial value in SI (a constant)");
    }
    builder.SetInitialState(std::move(q0), std::move(u0));
    const std::vector<YAML::Node> constraint_items = internal::ReadConstraints(c, root);
    multibody::Model model = std::move(builder).Build();
    internal::CheckConstraintsAtInitialState(c, root, constraint_items, model);
    return {file.name, file.description, parameters, std::move(model), std::move(stiffness)};
  } catch (const ModelError& e) {
    std::string which;
    if (c.num_coordinates > multibody::kMaxJetCoordinates && !c.first_general.empty()) {
      which = fmt::format("; the first non-affine kinematic expression is {} (write angles and "
                          "positions affine in the coordinates to lift the cap)", c.first_general);
    }
    throw ConfigError(fmt::format("{}: {}{}", in.path(), e.what(), which));
  } catch (const YAML::Exception& e) {
    // A reader that touched a missing key: should not happen (every required key is checked
    // with its place), but never let yaml-cpp's "line 0, column 0" reach the user alone.
    throw ConfigError(fmt::format("{}: {} (a required key is missing or has the wrong kind; "
                                  "compare with docs/model-files.md)", in.path(), e.what()));
  }
}

namespace internal {

YAML::Node FileContext::Require(const YAML::Node& parent, const std::string& key,
                               const std::string& kp, const std::string& expected) const {
  YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) {
    throw ConfigError(fmt::format("{}.{}: missing; expected {}; add `{}: ...` to {}",
                                  Where(parent, kp), key, expected, key, kp));
  }
  return node;
}

void FileContext::RequireVector3(const YAML::Node& node, const std::string& kp,
                                 const std::string& expected) const {
  if (node.IsSequence() && node.size() == 3) return;
  std::string hint;
  if (node.IsSequence()) {
    bool unbalanced = false;  // an item with unbalanced parentheses: split at a comma
    for (const auto& item : node) {
      if (!item.IsScalar()) continue;
      int open = 0;
      for (char ch : item.Scalar()) open += ch == '(' ? 1 : ch == ')' ? -1 : 0;
      unbalanced = unbalanced || open != 0;
    }
    if (unbalanced) {
      hint = "; a formula with a comma inside [...] must be quoted, e.g. [\"pow(L, 2)\", 0, 0], "
             "or YAML splits it at the comma";
    }
  }
  if (!node.IsDefined() || node.IsNull()) in.ThrowValue(node, kp, expected);
  throw ConfigError(fmt::format("{}: expected {}{}", Where(node, kp), expected, hint));
}

Expression FileContext::Parse(const YAML::Node& node, const std::string& key_path, Dim want) const {
  if (!node.IsDefined() || node.IsNull() || !node.IsScalar()) {
    in.ThrowValue(node, key_path, "a number or a formula such as `l * cos(q1)`");
  }
  const std::string text = node.Scalar();
  try {
    Expression e = Expression::Parse(text, symbols);
    CheckDim(node, key_path, e, want);
    return e;
  } catch (const ExpressionError& e) {
    std::string message = e.message;
    if (std::find(slot_names.begin(), slot_names.end(), e.token) != slot_names.end()) {
      message = fmt::format("'{}' is a slot (a restoring force); slots may appear only in forces "
                            "and torques; angles, positions and displacements use t, the "
                            "coordinates and parameters", e.token);
    }
    const std::string shown = text.size() > 120 ? text.substr(0, 100) + " …" : text;
    throw ConfigError(fmt::format("{} = '{}': at '{}' (column {}): {}", Where(node, key_path),
                                  shown, e.token.substr(0, 40), e.column + 1, message));
  }
}

void FileContext::CheckDim(const YAML::Node& node, const std::string& key_path,
                           const Expression& e, const Dim& want) const {
  if (want.known && e.dim().known && e.dim().e != want.e) {
    throw ConfigError(fmt::format("{} = '{}': is in {}, but {} is expected here (radians count "
                                  "as 1); check the formula and its parameters' units",
                                  Where(node, key_path), node.Scalar(), DimName(e.dim()),
                                  DimName(want)));
  }
}

Expression FileContext::ParseKinematic(const YAML::Node& node, const std::string& key_path,
                                       Dim want) const {
  Expression e = Parse(node, key_path);
  if (e.Uses(Op::kSpeed) || e.Uses(Op::kSlot) || e.Uses(Op::kTimeFunction) ||
      e.Uses(Op::kState)) {
    throw ConfigError(fmt::format("{} = '{}': reads a speed, a slot, a state or a time function; "
                                  "angles, positions, displacements and W(q) may use only t, the "
                                  "coordinates and parameters (write speeds and states into "
                                  "loads)",
                                  Where(node, key_path), node.Scalar()));
  }
  CheckDim(node, key_path, e, want);
  return e;
}

double FileContext::Constant(const YAML::Node& node, const std::string& key_path,
                             const std::string& expected, Dim want) const {
  const Expression e = Parse(node, key_path);
  if (!e.is_constant() || !std::isfinite(e.constant_value())) {
    throw ConfigError(fmt::format("{} = '{}': expected {}, a constant (numbers and parameters "
                                  "only, no t, coordinates, speeds or slots)",
                                  Where(node, key_path), node.Scalar(), expected));
  }
  CheckDim(node, key_path, e, want);
  return e.constant_value();
}

multibody::ScalarField FileContext::Field(const YAML::Node& node, const std::string& key_path,
                                          Dim want) const {
  Expression e = ParseKinematic(node, key_path, want);
  const LinearForm f = Linearize(e);
  if (f.affine) {
    std::vector<multibody::ScalarField::Term> terms;
    double time_rate = 0.0;
    for (const LinearForm::Term& t : f.terms) {
      if (t.kind == Op::kTime) {
        time_rate += t.coefficient;
      } else {
        terms.push_back({t.index, t.coefficient});
      }
    }
    return multibody::ScalarField::Affine(f.constant, std::move(terms), time_rate);
  }
  if (first_general.empty()) {
    first_general = fmt::format("{} = '{}'", Where(node, key_path), node.Scalar());
  }
  auto shared = std::make_shared<const Expression>(std::move(e));
  return multibody::ScalarField::Function([shared](const auto& a) {
    using J = std::decay_t<decltype(a.t)>;
    const Variables<J> v{a.t, a.q, {}, {}, {}};
    return Evaluate(*shared, v);
  });
}

multibody::FrameId FileContext::Frame(const YAML::Node& node, const std::string& key_path) const {
  const std::string name = in.String(node, key_path, "a frame name (N or one under frames:)");
  const auto it = frames.find(name);
  if (it != frames.end()) return it->second;
  SymbolTable known;
  for (const auto& kv : frames) known.Add({kv.first, Op::kConst, -1, 0.0});
  std::string hint;
  for (const std::string& s : known.Closest(name)) hint += (hint.empty() ? "" : ", ") + s;
  throw ConfigError(fmt::format("{} = '{}': unknown frame; did you mean {}? (a frame must be "
                                "declared under frames: before it is used)",
                                Where(node, key_path), name, hint));
}

multibody::PointId FileContext::Point(const YAML::Node& node, const std::string& key_path) const {
  const std::string name = in.String(node, key_path, "a point name (O or one under points:)");
  const auto it = points.find(name);
  if (it != points.end()) return it->second;
  SymbolTable known;
  for (const auto& kv : points) known.Add({kv.first, Op::kConst, -1, 0.0});
  std::string hint;
  for (const std::string& s : known.Closest(name)) hint += (hint.empty() ? "" : ", ") + s;
  throw ConfigError(fmt::format("{} = '{}': unknown point; did you mean {}? (a point must be "
                                "declared under points: before it is used)",
                                Where(node, key_path), name, hint));
}

}  // namespace internal
}  // namespace hybridtest::modelfile
