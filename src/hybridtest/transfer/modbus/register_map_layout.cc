// See register_map.h: the rules of one actuator's map and of several actuators' blocks, and
// the requests that write and read them. The YAML is read in register_map_parse.cc.
#include "hybridtest/transfer/modbus/register_map.h"

#include <fmt/core.h>

#include <algorithm>
#include <limits>
#include <utility>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::modbus {
namespace {

const char* TableName(Table table) { return table == Table::kHolding ? "holding" : "input"; }

// The span of one actuator's readout registers per table (the rule: at most 125 each).
std::vector<RegisterBlock> ReadoutSpans(const RegisterMap& map) {
  std::vector<RegisterBlock> blocks;
  for (Table table : {Table::kInput, Table::kHolding}) {
    int start = std::numeric_limits<int>::max(), end = -1;
    for (const RegisterField* f : {&map.position, &map.force, &map.ack}) {
      if (f->table != table) continue;
      start = std::min(start, f->address);
      end = std::max(end, f->end());
    }
    for (const auto* f : {&map.status, &map.lab_time}) {
      if (!f->has_value() || (*f)->table != table) continue;
      start = std::min(start, (*f)->address);
      end = std::max(end, (*f)->end());
    }
    if (end >= 0) blocks.push_back({table, start, end - start});
  }
  return blocks;
}

void ValidateRegisterMap(const RegisterMap& map, const std::string& where) {
  const auto fail = [&](const std::string& what) {
    throw ConfigError(fmt::format("{}: {}", where, what));
  };
  std::vector<std::pair<std::string, const RegisterField*>> fields = {
      {"command", &map.command}, {"sequence", &map.sequence}, {"position", &map.position},
      {"force", &map.force},     {"ack", &map.ack}};
  if (map.status) fields.emplace_back("status", &*map.status);
  if (map.lab_time) fields.emplace_back("lab_time", &*map.lab_time);
  for (const auto& [name, f] : fields) {
    if (f->address < 0 || f->end() > 65536) {
      fail(fmt::format("{}.address = {}: expected an address in 0..{}", name, f->address,
                       65536 - f->width()));
    }
    if (!(std::abs(f->scale) > 0.0) || !std::isfinite(f->scale)) {
      fail(fmt::format("{}.scale = {}: expected a non-zero finite factor", name, f->scale));
    }
  }
  // The sequence, the ack and the status are counts and bits, not scaled floats.
  for (const auto& [name, f] : {std::pair{"sequence", &map.sequence}, std::pair{"ack", &map.ack}}) {
    if ((f->type != ValueType::kUint16 && f->type != ValueType::kUint32) || f->scale != 1.0) {
      fail(fmt::format("{}: expected type uint16 or uint32 with scale 1 (a sequence number)", name));
    }
  }
  if (map.ack.type != map.sequence.type) {
    fail("ack and sequence: expected the same type (both uint16 or both uint32)");
  }
  if (map.status && (map.status->type != ValueType::kUint16 || map.status->scale != 1.0)) {
    fail("status: expected type uint16 with scale 1 (a register of bits)");
  }
  for (int bit : {map.status_bits.enabled, map.status_bits.fault, map.status_bits.holding}) {
    if (bit < -1 || bit > 15) fail(fmt::format("status bit {}: expected 0..15, or -1 (unused)", bit));
  }
  // Fields of one table must not overlap.
  for (std::size_t i = 0; i < fields.size(); ++i) {
    for (std::size_t j = i + 1; j < fields.size(); ++j) {
      const RegisterField& a = *fields[i].second;
      const RegisterField& b = *fields[j].second;
      if (a.table == b.table && a.address < b.end() && b.address < a.end()) {
        fail(fmt::format("{} ({}) and {} ({}) overlap; give each its own registers",
                         fields[i].first, DescribeField(a), fields[j].first, DescribeField(b)));
      }
    }
  }
  // One write (function 16) carries the command and its sequence: adjacent holding registers.
  if (map.command.table != Table::kHolding || map.sequence.table != Table::kHolding) {
    fail("command and sequence: expected holding registers (they are written)");
  }
  const RegisterBlock write = CommandBlock(map);
  if (write.count != map.command.width() + map.sequence.width()) {
    fail(fmt::format("command ({}) and sequence ({}) must be adjacent so that one request "
                     "(function 16) writes both; move the sequence next to the command",
                     DescribeField(map.command), DescribeField(map.sequence)));
  }
  for (const RegisterBlock& b : ReadoutSpans(map)) {
    if (b.count > 125) {
      fail(fmt::format("the {} registers read back span {} registers ({}..{}); one request "
                       "reads at most 125: place position, force, ack, status and lab_time "
                       "closer together", TableName(b.table), b.count, b.start,
                       b.start + b.count - 1));
    }
  }
  if (map.enable_coil && map.hold_coil && *map.enable_coil == *map.hold_coil) {
    fail(fmt::format("enable_coil and hold_coil are both coil {}: expected two coils",
                     *map.enable_coil));
  }
  for (const auto& coil : {map.enable_coil, map.hold_coil}) {
    if (coil && (*coil < 0 || *coil > 65535)) {
      fail(fmt::format("coil {}: expected an address in 0..65535", *coil));
    }
  }
}


struct NamedField {
  std::string name;  // "actuator 2's force", or "lab_time"
  const RegisterField* field;
};

// Every register field of actuator k's map ("command", ...), not the lab time.
std::vector<std::pair<const char*, const RegisterField*>> OwnFields(const RegisterMap& m) {
  std::vector<std::pair<const char*, const RegisterField*>> fields = {
      {"command", &m.command}, {"sequence", &m.sequence}, {"position", &m.position},
      {"force", &m.force},     {"ack", &m.ack}};
  if (m.status) fields.emplace_back("status", &*m.status);
  return fields;
}

// The readout fields (position, force, ack, status) of each actuator in `table`, and the lab
// time, as spans [start, end): one per actuator and table (its fields are read together).
std::vector<std::pair<int, int>> ReadSpans(const std::vector<RegisterMap>& maps, Table table) {
  std::vector<std::pair<int, int>> spans;
  for (const RegisterMap& m : maps) {
    int start = std::numeric_limits<int>::max(), end = -1;
    for (const auto* f : {&m.position, &m.force, &m.ack}) {
      if (f->table != table) continue;
      start = std::min(start, f->address);
      end = std::max(end, f->end());
    }
    if (m.status && m.status->table == table) {
      start = std::min(start, m.status->address);
      end = std::max(end, m.status->end());
    }
    if (end >= 0) spans.emplace_back(start, end);
    if (m.lab_time && m.lab_time->table == table) {
      spans.emplace_back(m.lab_time->address, m.lab_time->end());
    }
  }
  std::sort(spans.begin(), spans.end());
  return spans;
}

// Span of actuator 1's fields in `table` (lab time excluded); 0 if it has none there.
int Span(const RegisterMap& m, Table table) {
  int start = std::numeric_limits<int>::max(), end = -1;
  for (const auto& [name, f] : OwnFields(m)) {
    if (f->table != table) continue;
    start = std::min(start, f->address);
    end = std::max(end, f->end());
  }
  return end < 0 ? 0 : end - start;
}

void AddCoil(std::vector<int>& coils, const std::optional<int>& coil) {
  if (coil && std::find(coils.begin(), coils.end(), *coil) == coils.end()) coils.push_back(*coil);
}

}  // namespace

RegisterMap StridedMap(const RegisterMap& base, const Stride& stride, int k) {
  RegisterMap m = base;
  if (k == 0) return m;
  const int holding = stride.holding.value_or(Span(base, Table::kHolding));
  const int input = stride.input.value_or(Span(base, Table::kInput));
  int coils = 0;
  if (stride.coils) {
    coils = *stride.coils;
  } else if (base.enable_coil || base.hold_coil) {
    const int lo = std::min(base.enable_coil.value_or(std::numeric_limits<int>::max()),
                            base.hold_coil.value_or(std::numeric_limits<int>::max()));
    const int hi = std::max(base.enable_coil.value_or(-1), base.hold_coil.value_or(-1));
    coils = hi - lo + 1;
  }
  for (RegisterField* f : {&m.command, &m.sequence, &m.position, &m.force, &m.ack}) {
    f->address += k * (f->table == Table::kHolding ? holding : input);
  }
  if (m.status) m.status->address += k * (m.status->table == Table::kHolding ? holding : input);
  if (m.enable_coil) *m.enable_coil += k * coils;
  if (m.hold_coil) *m.hold_coil += k * coils;
  m.lab_time.reset();
  return m;
}

std::vector<WriteBlock> CommandWrites(const std::vector<RegisterMap>& maps) {
  std::vector<int> order(maps.size());
  for (std::size_t k = 0; k < maps.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return CommandBlock(maps[static_cast<std::size_t>(a)]).start <
           CommandBlock(maps[static_cast<std::size_t>(b)]).start;
  });
  std::vector<WriteBlock> writes;
  for (int k : order) {
    const RegisterBlock b = CommandBlock(maps[static_cast<std::size_t>(k)]);
    if (!writes.empty()) {
      RegisterBlock& last = writes.back().block;
      if (last.start + last.count == b.start && last.count + b.count <= kMaxWriteRegisters) {
        last.count += b.count;
        writes.back().actuators.push_back(k);
        continue;
      }
    }
    writes.push_back({b, {k}});
  }
  return writes;
}

std::vector<RegisterBlock> ReadoutBlocks(const std::vector<RegisterMap>& maps) {
  std::vector<RegisterBlock> blocks;
  for (Table table : {Table::kInput, Table::kHolding}) {
    const std::size_t first = blocks.size();  // this table's blocks start here
    for (const auto& [start, end] : ReadSpans(maps, table)) {
      if (blocks.size() > first && end - blocks.back().start <= kMaxReadRegisters) {
        blocks.back().count = std::max(blocks.back().count, end - blocks.back().start);
      } else {
        blocks.push_back({table, start, end - start});
      }
    }
  }
  return blocks;
}

std::vector<int> EnableCoils(const std::vector<RegisterMap>& maps) {
  std::vector<int> coils;
  for (const RegisterMap& m : maps) AddCoil(coils, m.enable_coil);
  return coils;
}

std::vector<int> HoldCoils(const std::vector<RegisterMap>& maps) {
  std::vector<int> coils;
  for (const RegisterMap& m : maps) AddCoil(coils, m.hold_coil);
  return coils;
}

void ValidateRegisterMaps(const std::vector<RegisterMap>& maps, const std::string& where,
                          const std::string& fix) {
  if (maps.empty()) throw ConfigError(fmt::format("{}: expected at least one actuator", where));
  const std::size_t n = maps.size();
  for (std::size_t k = 0; k < n; ++k) {
    ValidateRegisterMap(maps[k], n == 1 ? where : fmt::format("{} (actuator {})", where, k + 1));
  }
  if (n == 1) return;
  // Registers: no two actuators share one, and none is the lab time's.
  std::vector<NamedField> fields;
  for (std::size_t k = 0; k < n; ++k) {
    for (const auto& [name, f] : OwnFields(maps[k])) {
      fields.push_back({fmt::format("actuator {}'s {}", k + 1, name), f});
    }
  }
  const auto owner = [](const std::string& name) { return name.substr(0, name.find('\'')); };
  std::vector<NamedField> checked = fields;
  if (maps[0].lab_time) checked.push_back({"lab_time", &*maps[0].lab_time});
  for (std::size_t i = 0; i < checked.size(); ++i) {
    for (std::size_t j = i + 1; j < checked.size(); ++j) {
      const RegisterField& a = *checked[i].field;
      const RegisterField& b = *checked[j].field;
      if (owner(checked[i].name) == owner(checked[j].name)) continue;  // checked per map
      if (a.table == b.table && a.address < b.end() && b.address < a.end()) {
        throw ConfigError(fmt::format(
            "{}: {} ({}) and {} ({}) overlap: every actuator needs registers of its own{}", where,
            checked[i].name, DescribeField(a), checked[j].name, DescribeField(b), fix));
      }
    }
  }
  // Coils: one actuator's, or the same role for every actuator that names it.
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const auto& a = maps[i];
      const auto& b = maps[j];
      if (a.enable_coil && b.hold_coil && *a.enable_coil == *b.hold_coil) {
        throw ConfigError(fmt::format(
            "{}: coil {} is actuator {}'s enable_coil and actuator {}'s hold_coil: a coil is "
            "either an enable or a hold; give each its own coil{}", where, *a.enable_coil, i + 1,
            j + 1, fix));
      }
    }
  }
}

}  // namespace hybridtest::transfer::modbus
