// See simcor_codec.h.
#include "hybridtest/transfer/site/simcor_codec.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <string_view>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"

namespace hybridtest::transfer::site::simcor {
namespace {

constexpr std::string_view kSimcorSupported =
    "open-session, propose, execute, get-control-point, close-session";

bool SimcorTextByte(std::uint8_t b) { return b == '\t' || (b >= 0x20 && b < 0x7F); }

// The line without its LF and an optional CR before it.
std::string_view SimcorBody(std::span<const std::uint8_t> line) {
  std::string_view s(reinterpret_cast<const char*>(line.data()), line.size());
  if (!s.empty() && s.back() == '\n') s.remove_suffix(1);
  if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> SimcorFields(std::string_view body) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t tab = body.find('\t', start);
    fields.push_back(body.substr(start, tab == std::string_view::npos ? tab : tab - start));
    if (tab == std::string_view::npos) return fields;
    start = tab + 1;
  }
}

bool SimcorNameChar(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
         c == '-' || c == '_' || c == '.';
}

long SimcorInt(std::string_view text, std::string_view what, std::string_view field) {
  long v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < -1 || v > 1000000000L) {
    throw TransferError(fmt::format("transaction id '{}': {} '{}' is not an integer from -1 to "
                                    "1e9", Printable(field), what, Printable(text)));
  }
  return v;
}

// NAME or NAME[STEP SUBSTEP CORRECTION] → the site's TransactionId.
TransactionId SimcorId(std::string_view field) {
  const std::size_t open = field.find('[');
  const std::string_view name = field.substr(0, open);
  bool ok = !name.empty() && name.size() <= 30;  // the key stays within kMaxRunTagBytes
  for (char c : name) ok = ok && SimcorNameChar(c);
  if (!ok) {
    throw TransferError(fmt::format("field 2: transaction id '{}': expected a name of 1 to 30 "
                                    "letters, digits, '-', '_' or '.' (e.g. trans20240101120000"
                                    ".000[12 0 0])", Printable(field)));
  }
  TransactionId id;
  id.run = std::string(name);
  id.seq = 1;
  id.step = -1;
  if (open == std::string_view::npos) return id;
  if (field.back() != ']') {
    throw TransferError(fmt::format("field 2: transaction id '{}': expected NAME[STEP SUBSTEP "
                                    "CORRECTION] ending in ']'", Printable(field)));
  }
  const std::string_view inner = field.substr(open + 1, field.size() - open - 2);
  const std::size_t a = inner.find(' ');
  const std::size_t b = a == std::string_view::npos ? a : inner.find(' ', a + 1);
  if (a == std::string_view::npos || b == std::string_view::npos ||
      inner.find(' ', b + 1) != std::string_view::npos) {
    throw TransferError(fmt::format("field 2: transaction id '{}': expected three integers in "
                                    "the brackets, separated by one space", Printable(field)));
  }
  id.step = SimcorInt(inner.substr(0, a), "step", field);
  id.stage = static_cast<int>(SimcorInt(inner.substr(a + 1, b - a - 1), "substep", field));
  id.attempt = static_cast<int>(SimcorInt(inner.substr(b + 1), "correction step", field));
  id.run = fmt::format("{}-{}-{}-{}", name, id.step, id.stage, id.attempt);
  return id;
}

bool SimcorAddress(std::string_view f) { return f.find("MDL") != std::string_view::npos; }

double SimcorValue(std::string_view text, std::size_t field) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    throw TransferError(fmt::format("field {}: displacement '{}': expected a finite number",
                                    field, Printable(text)));
  }
  return v;
}

// propose's content: (ADDRESS (AXIS displacement VALUE)+)+ from field index `i`.
void SimcorTargets(const std::vector<std::string_view>& f, Request& r) {
  std::string address;
  for (std::size_t i = 2; i < f.size();) {
    if (SimcorAddress(f[i])) {
      address = std::string(f[i]);
      if (i + 1 >= f.size() || SimcorAddress(f[i + 1])) {
        throw TransferError(fmt::format("field {}: address {} without a value: expected AXIS "
                                        "displacement VALUE after it", i + 1, Printable(address)));
      }
      ++i;
      continue;
    }
    if (address.empty()) {
      throw TransferError(fmt::format("field {}: '{}' before any address: expected "
                                      "MDL-xx-yy:POINT first", i + 1, Printable(f[i])));
    }
    if (i + 3 > f.size()) {
      throw TransferError(fmt::format("field {}: an incomplete triple: expected AXIS "
                                      "displacement VALUE", i + 1));
    }
    if (f[i] != "x" && f[i] != "y" && f[i] != "z") {
      throw TransferError(fmt::format("field {}: axis '{}': expected x, y or z", i + 1,
                                      Printable(f[i])));
    }
    if (f[i + 1] != "displacement") {
      throw TransferError(fmt::format("field {}: quantity '{}' is not supported: a hybridtest "
                                      "site's actuators each take one displacement", i + 2,
                                      Printable(f[i + 1])));
    }
    if (r.targets.size() == kMaxValues) {
      throw TransferError(fmt::format("more than {} displacements in one propose", kMaxValues));
    }
    r.targets.push_back(SimcorValue(f[i + 2], i + 3));
    r.points.push_back({address, std::string(f[i])});
    i += 3;
  }
  if (r.targets.empty()) {
    throw TransferError("propose without a target: expected ADDRESS x displacement VALUE");
  }
}

std::string SimcorClean(const std::string& text) {
  std::string out;
  for (char c : text.substr(0, 1000)) {
    out.push_back(SimcorTextByte(static_cast<std::uint8_t>(c)) && c != '\t' ? c : ' ');
  }
  for (std::size_t at = 0; (at = out.find("MDL", at)) != std::string::npos;) {
    out.replace(at, 3, "mdl");
  }
  return out.empty() ? std::string("-") : out;
}

}  // namespace

bool BeginsLine(std::uint8_t first) { return first >= 'a' && first <= 'z'; }

std::size_t MeasureLine(std::span<const std::uint8_t> bytes) {
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (bytes[i] == '\n') return i + 1;
    if (!SimcorTextByte(bytes[i]) && bytes[i] != '\r') {
      throw TransferError(fmt::format("UI-SimCor line: byte 0x{:02X} at column {}: expected "
                                      "printable ASCII fields separated by TAB, ended by LF",
                                      bytes[i], i + 1));
    }
    if (i + 1 >= kMaxLineBytes) {
      throw TransferError(fmt::format("UI-SimCor line longer than {} bytes without its LF",
                                      kMaxLineBytes));
    }
  }
  return bytes.size() + 1;
}

Request ParseLine(std::span<const std::uint8_t> line) {
  const std::string_view body = SimcorBody(line);
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (!SimcorTextByte(static_cast<std::uint8_t>(body[i]))) {
      throw TransferError(fmt::format("byte 0x{:02X} at column {}: expected printable ASCII",
                                      static_cast<std::uint8_t>(body[i]), i + 1));
    }
  }
  const std::vector<std::string_view> f = SimcorFields(body);
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f[i].empty()) {
      throw TransferError(fmt::format("field {} is empty: fields are separated by one TAB",
                                      i + 1));
    }
  }
  Request r;
  const std::string_view command = f[0];
  if (command == "open-session" || command == "close-session") {
    r.command = command == "open-session" ? Command::kOpenSession : Command::kCloseSession;
    r.echo = f.size() > 1 ? std::string(f[1]) : std::string(command);
    return r;
  }
  if (command != "propose" && command != "execute" && command != "get-control-point") {
    throw TransferError(fmt::format("command '{}' is not supported by a hybridtest site "
                                    "(supported: {})", Printable(command), kSimcorSupported));
  }
  if (f.size() < 2) {
    throw TransferError(fmt::format("{} without a transaction id (field 2)", command));
  }
  r.echo = std::string(f[1]);
  if (command == "propose") {
    r.command = Command::kPropose;
    r.id = SimcorId(f[1]);
    SimcorTargets(f, r);
  } else if (command == "execute") {
    r.command = Command::kExecute;
    r.id = SimcorId(f[1]);
  } else {
    r.command = Command::kGetControlPoint;
    r.dummy = f[1] == "dummy";
    if (!r.dummy) r.id = SimcorId(f[1]);
    for (std::size_t i = 2; i < f.size(); ++i) {
      if (!SimcorAddress(f[i]) || r.points.size() == kMaxAddresses) {
        throw TransferError(fmt::format("field {}: '{}': expected up to {} addresses "
                                        "(MDL-xx-yy:POINT)", i + 1, Printable(f[i]),
                                        kMaxAddresses));
      }
      r.points.push_back({std::string(f[i]), ""});
    }
    if (r.points.empty()) {
      throw TransferError("get-control-point without an address (field 3): expected "
                          "MDL-xx-yy:POINT");
    }
  }
  return r;
}

std::string EchoOf(std::span<const std::uint8_t> line) {
  const std::vector<std::string_view> f = SimcorFields(SimcorBody(line));
  if (f.size() < 2 || f[1].empty() || f[1].size() > 64 || SimcorAddress(f[1])) return "error";
  for (char c : f[1]) {
    if (!SimcorNameChar(c) && c != '[' && c != ']' && c != ' ') return "error";
  }
  return std::string(f[1]);
}

std::string FormatOk(const std::string& echo, const std::string& text) {
  return fmt::format("OK\t0\t{}\t{}\n", echo, SimcorClean(text));
}

std::string FormatNotOk(const std::string& echo, const std::string& reason) {
  return fmt::format("NOT OK\t0\t{}\t{}\n", echo, SimcorClean(reason));
}

std::string FormatControlPoints(const std::string& echo, std::span<const PointReading> points) {
  std::string out = "OK\t0\t" + echo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointReading& p = points[i];
    if (i == 0 || points[i - 1].point.address != p.point.address) out += "\t" + p.point.address;
    out += fmt::format("\t{0}\tdisplacement\t{1:.17g}\t{0}\tforce\t{2:.17g}", p.point.axis,
                       p.measured.position, p.measured.force);
  }
  return out + "\n";
}

}  // namespace hybridtest::transfer::site::simcor
