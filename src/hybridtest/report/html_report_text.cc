#include "hybridtest/report/html_report_text.h"

#include <fmt/core.h>

#include <cmath>
#include <string>

namespace hybridtest::report {

std::string EscapeHtml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string EncodeBase64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += two ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string FormatNumber(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return fmt::format("{:.6g}", value);
}

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds)) return FormatNumber(seconds) + " s";
  std::string out = (std::abs(seconds) >= 1000 ? fmt::format("{:.0f}", seconds)
                                               : fmt::format("{:.4g}", seconds)) + " s";
  if (seconds < 60) return out;
  const long total = std::lround(seconds);
  const long h = total / 3600, min = (total % 3600) / 60, s = total % 60;
  if (h > 0) return out + fmt::format(" ({} h {} min)", h, min);
  return out + fmt::format(" ({} min {} s)", min, s);
}

namespace {

// A copy with every number rounded as FormatNumber rounds it (6 significant digits), so that
// nested records read without float noise (2.5140000000000002 → 2.514).
nlohmann::json Rounded(const nlohmann::json& value) {
  if (value.is_number_float()) {
    const double v = value.get<double>();
    return std::isfinite(v) ? nlohmann::json(std::stod(fmt::format("{:.6g}", v))) : value;
  }
  if (!value.is_structured()) return value;
  nlohmann::json out = value;
  for (auto& item : out) item = Rounded(item);
  return out;
}

}  // namespace

std::string FormatJson(const nlohmann::json& value) {
  if (value.is_number()) return FormatNumber(value.get<double>());
  if (value.is_string()) return value.get<std::string>();
  if (value.is_null()) return "";
  return Rounded(value).dump();
}

}  // namespace hybridtest::report
