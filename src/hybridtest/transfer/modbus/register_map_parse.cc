// See register_map.h: ParseRegisterMaps, the `map:` mapping of a Modbus transfer.
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/units.h"
#include "hybridtest/transfer/modbus/register_map.h"

namespace hybridtest::transfer::modbus {
namespace {

bool IsNone(const YAML::Node& node) {
  return node.IsNull() || (node.IsScalar() && node.Scalar() == "none");
}

// `check_keys`: false when the caller has checked the keys (a field with more keys).
void ParseField(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                RegisterField& field, bool check_keys = true) {
  in.RequireMapping(node, kp);
  if (check_keys) in.CheckKeys(node, kp, {"table", "address", "type", "scale"});
  if (node["table"]) {
    const std::string t = in.String(node["table"], kp + ".table", "holding or input");
    if (t == "holding") {
      field.table = Table::kHolding;
    } else if (t == "input") {
      field.table = Table::kInput;
    } else {
      in.ThrowValue(node["table"], kp + ".table", "holding or input");
    }
  }
  if (node["address"]) {
    field.address = in.Integer(node["address"], kp + ".address",
                               "a 0-based register address (holding 40001 is address 0)");
  }
  if (node["type"]) {
    const std::string t = in.String(node["type"], kp + ".type", "a register type");
    static const std::pair<const char*, ValueType> kTypes[] = {
        {"int16", ValueType::kInt16},     {"uint16", ValueType::kUint16},
        {"int32", ValueType::kInt32},     {"uint32", ValueType::kUint32},
        {"float32", ValueType::kFloat32}, {"float64", ValueType::kFloat64}};
    bool found = false;
    for (const auto& [name, type] : kTypes) {
      if (t == name) {
        field.type = type;
        found = true;
      }
    }
    if (!found) {
      in.ThrowValue(node["type"], kp + ".type",
                    "int16, uint16, int32, uint32, float32 or float64");
    }
  }
  field.scale = in.ReadNumber(node, kp, "scale", "a non-zero factor: value = raw × scale",
                              field.scale);
}

std::optional<int> ParseCoil(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                             std::optional<int> fallback) {
  if (!node.IsDefined()) return fallback;
  if (IsNone(node)) return std::nullopt;
  return in.Integer(node, kp, "a 0-based coil address, or none");
}

void ParseUnits(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                BenchUnits& units) {
  in.RequireMapping(node, kp);
  in.CheckKeys(node, kp, {"length", "force"});
  const std::string length = in.ReadString(node, kp, "length", units.length_name);
  const std::string force = in.ReadString(node, kp, "force", units.force_name);
  if (length == "mm") {
    units.metres_per_length_unit = units::kMillimetre;
  } else if (length == "m") {
    units.metres_per_length_unit = 1.0;
  } else {
    in.ThrowValue(node["length"], kp + ".length", "mm or m");
  }
  if (force == "N") {
    units.newtons_per_force_unit = 1.0;
  } else if (force == "kN") {
    units.newtons_per_force_unit = units::kKilonewton;
  } else {
    in.ThrowValue(node["force"], kp + ".force", "N or kN");
  }
  units.length_name = length;
  units.force_name = force;
}

// The fields one actuator has of its own: command, sequence, position, force, ack, status and
// the coils; each given field starts from `map`'s.
void ApplyActuatorFields(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                         RegisterMap& map) {
  const std::pair<const char*, RegisterField*> fields[] = {
      {"command", &map.command}, {"sequence", &map.sequence}, {"position", &map.position},
      {"force", &map.force},     {"ack", &map.ack}};
  for (const auto& [name, field] : fields) {
    if (node[name]) ParseField(in, node[name], JoinKeyPath(kp, name), *field);
  }
  if (const YAML::Node s = node["status"]; s.IsDefined()) {
    if (IsNone(s)) {
      map.status.reset();
    } else {
      const std::string skp = kp + ".status";
      in.RequireMapping(s, skp);
      in.CheckKeys(s, skp, {"table", "address", "type", "enabled_bit", "fault_bit", "holding_bit"});
      ParseField(in, s, skp, *map.status, false);
      const auto bit = [&](const char* key, int fallback) {
        return s[key] ? in.Integer(s[key], skp + "." + key, "a bit number 0..15, or -1 (unused)")
                      : fallback;
      };
      map.status_bits.enabled = bit("enabled_bit", map.status_bits.enabled);
      map.status_bits.fault = bit("fault_bit", map.status_bits.fault);
      map.status_bits.holding = bit("holding_bit", map.status_bits.holding);
    }
  }
  map.enable_coil = ParseCoil(in, node["enable_coil"], kp + ".enable_coil", map.enable_coil);
  map.hold_coil = ParseCoil(in, node["hold_coil"], kp + ".hold_coil", map.hold_coil);
}

// The map of actuator 1 with the controller's settings (the keys of several actuators are
// read by the caller).
RegisterMap ParseBaseMap(const YamlInput& in, const YAML::Node& node, const std::string& kp) {
  RegisterMap map;
  if (!node.IsDefined() || node.IsNull()) return map;
  in.RequireMapping(node, kp);
  in.CheckKeys(node, kp, {"units", "word_order", "byte_order", "command", "sequence", "position",
                          "force", "ack", "status", "lab_time", "enable_coil", "hold_coil",
                          "actuators", "stride", "per_actuator"});
  if (node["units"]) ParseUnits(in, node["units"], kp + ".units", map.units);
  if (node["word_order"]) {
    const std::string w = in.String(node["word_order"], kp + ".word_order", "a word order");
    if (w == "high_first") {
      map.word_order = WordOrder::kHighFirst;
    } else if (w == "low_first") {
      map.word_order = WordOrder::kLowFirst;
    } else {
      in.ThrowValue(node["word_order"], kp + ".word_order",
                    "high_first (big-endian, 'ABCD') or low_first (word-swapped, 'CDAB')");
    }
  }
  if (node["byte_order"]) {
    const std::string b = in.String(node["byte_order"], kp + ".byte_order", "a byte order");
    if (b == "big") {
      map.byte_order = ByteOrder::kBig;
    } else if (b == "little") {
      map.byte_order = ByteOrder::kLittle;
    } else {
      in.ThrowValue(node["byte_order"], kp + ".byte_order",
                    "big (the Modbus standard) or little (bytes swapped inside each register)");
    }
  }
  ApplyActuatorFields(in, node, kp, map);
  if (const YAML::Node l = node["lab_time"]; l.IsDefined() && !IsNone(l)) {
    map.lab_time = RegisterField{Table::kInput, 6, ValueType::kFloat32};
    ParseField(in, l, kp + ".lab_time", *map.lab_time);
  }
  ValidateRegisterMaps({map}, in.Where(node, kp));
  return map;
}

}  // namespace

std::vector<RegisterMap> ParseRegisterMaps(const YamlInput& in, const YAML::Node& node,
                                           const std::string& kp) {
  if (!node.IsDefined() || node.IsNull()) return {RegisterMap{}};
  const RegisterMap base = ParseBaseMap(in, node, kp);
  const YAML::Node count = node["actuators"], list = node["per_actuator"];
  const std::string list_kp = kp + ".per_actuator";
  int n = 1;
  if (count) {
    n = static_cast<int>(in.Count(count, kp + ".actuators",
                                  "the number of actuators this controller drives (1..64)", 1, 64));
  }
  if (list) {
    if (!list.IsSequence() || list.size() == 0) {
      in.ThrowValue(list, list_kp, "a list of one mapping per actuator ({} keeps an actuator's "
                                   "strided fields)");
    }
    if (count && static_cast<int>(list.size()) != n) {
      throw ConfigError(fmt::format(
          "{}: {} entries for `actuators: {}`: give one entry per actuator ({{}} keeps an "
          "actuator's strided fields), or drop `actuators:`", in.Where(list, list_kp),
          list.size(), n));
    }
    n = static_cast<int>(list.size());
  }
  Stride stride;
  const YAML::Node s = node["stride"];
  if (s.IsDefined()) {
    const std::string skp = kp + ".stride";
    in.RequireMapping(s, skp);
    in.CheckKeys(s, skp, {"holding", "input", "coils"});
    const auto read = [&](const char* key, std::optional<int>& out) {
      if (!s[key]) return;
      out = static_cast<int>(in.Count(s[key], skp + "." + key,
                                      "the address offset from one actuator's registers to the "
                                      "next one's (0..65535; coils: 0 shares them)",
                                      0, 65535));
    };
    read("holding", stride.holding);
    read("input", stride.input);
    read("coils", stride.coils);
  }
  const std::string fix = fmt::format(
      ". Give {}.stride (holding, input, coils) of at least one actuator's block, or the "
      "fields of each actuator in {}", kp, list_kp);
  std::vector<RegisterMap> maps;
  for (int k = 0; k < n; ++k) {
    RegisterMap m = StridedMap(base, stride, k);
    std::string where = n == 1   ? in.Where(node, kp)
                        : k == 0 ? fmt::format("{} (actuator 1)", in.Where(node, kp))
                                 : fmt::format("{} (actuator {}: actuator 1's fields moved by {} "
                                               "× the stride)", in.Where(node, kp), k + 1, k);
    if (list) {
      const YAML::Node entry = list[static_cast<std::size_t>(k)];
      const std::string ekp = fmt::format("{}[{}]", list_kp, k);
      if (!entry.IsNull()) {
        in.RequireMapping(entry, ekp);
        in.CheckKeys(entry, ekp, {"command", "sequence", "position", "force", "ack", "status",
                                  "enable_coil", "hold_coil"});
        ApplyActuatorFields(in, entry, ekp, m);
        where = fmt::format("{} (actuator {})", in.Where(entry, ekp), k + 1);
      }
    }
    ValidateRegisterMaps({m}, where);
    maps.push_back(std::move(m));
  }
  ValidateRegisterMaps(maps, in.Where(node, kp), fix);
  return maps;
}

}  // namespace hybridtest::transfer::modbus
