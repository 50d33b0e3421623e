#pragma once
// Small text helpers for the HTML report: escaping, base64 for data URIs, number and duration
// formatting.
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace hybridtest::report {

// Text safe inside HTML elements and quoted attributes: & < > " ' are replaced by entities.
std::string EscapeHtml(std::string_view text);

// Standard base64 (RFC 4648, with padding).
std::string EncodeBase64(std::string_view bytes);

// A number with up to 6 significant digits ("2260", "0.0123", "1.5e-07"); "NaN"/"inf" as such.
std::string FormatNumber(double value);

// A duration in seconds, e.g. "22560 s (6 h 16 min)", "95.2 s (1 min 35 s)", "0.25 s"; at
// most 4 significant digits below an hour (a wall time is not known to the nanosecond).
std::string FormatDuration(double seconds);

// A JSON value as text: numbers with FormatNumber, strings as is, others as compact JSON with
// every number rounded to FormatNumber's 6 significant digits.
std::string FormatJson(const nlohmann::json& value);

}  // namespace hybridtest::report
