// A sidecar's text member, read without nlohmann::json::value(). GCC 12 at -O3 flags
// value(key, "") (the string default) with a -Wnull-dereference false positive inside json.hpp,
// in whichever translation unit instantiates it; find() and get_ref do not take that path.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace hybridtest::report {

// `object[key]` when `object` is an object whose `key` is a string; `fallback` otherwise.
inline std::string StringOr(const nlohmann::json& object, const char* key,
                            const std::string& fallback = "") {
  if (!object.is_object()) return fallback;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string()) return fallback;
  return it->get_ref<const std::string&>();
}

}  // namespace hybridtest::report
