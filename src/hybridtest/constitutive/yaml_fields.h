#pragma once
// Reading typed fields from a YAML mapping with errors that name the key path and the fix:
//   "bench.yaml: bench.actuator.delay_ms (line 12) = 'abc': expected a number in ms".
// Shared by every config parser of the constitutive and transfer layers.
// (It belongs in a lower layer once one parses YAML; see the bench branch report.)
#include <initializer_list>
#include <string>
#include <string_view>

#include <yaml-cpp/yaml.h>

namespace hybridtest::constitutive {

// "where.key", or "key" when `where` is empty.
std::string JoinKeyPath(std::string_view where, std::string_view key);

// Throws ConfigError unless `node` is a mapping; `where` names it.
void RequireMapping(const YAML::Node& node, std::string_view where);

// Throws ConfigError naming the first key of `node` that is not in `allowed` (catches typos).
void RequireKnownKeys(const YAML::Node& node, std::string_view where,
                      std::initializer_list<std::string_view> allowed);

// The number at node[key]. `expectation` says what is expected, with its unit, e.g.
// "a positive length in mm". Throws ConfigError when missing or not a finite number.
double ReadNumber(const YAML::Node& node, std::string_view where, const std::string& key,
                  std::string_view expectation);
// As above, but returns `fallback` when the key is absent.
double ReadNumber(const YAML::Node& node, std::string_view where, const std::string& key,
                  std::string_view expectation, double fallback);

// The string at node[key], or `fallback` when absent.
std::string ReadString(const YAML::Node& node, std::string_view where, const std::string& key,
                       std::string_view fallback);

// Throws ConfigError "where.key = value: expected ..." (with the line if known).
[[noreturn]] void ThrowField(const YAML::Node& node, std::string_view where,
                             std::string_view key, std::string_view value,
                             std::string_view expectation);

}  // namespace hybridtest::constitutive
