// See fmu_resources.h.
#include "fmu_resources.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"

namespace hybridtest::fmu_export {

std::string ResourceFolder(const std::string& location) {
  std::string path = location;
  if (path.rfind("file:", 0) == 0) {
    path = path.substr(5);
    if (path.rfind("//", 0) == 0) {  // file://host/path: only an empty host or localhost
      path = path.substr(2);
      if (path.rfind("localhost", 0) == 0) path = path.substr(9);
      if (path.empty() || path[0] != '/') {
        throw Error(fmt::format("resource location {}: a file URI of another host", location));
      }
    }
    std::string decoded;
    for (std::size_t i = 0; i < path.size(); ++i) {
      if (path[i] == '%' && i + 2 < path.size()) {
        decoded += static_cast<char>(std::stoi(path.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        decoded += path[i];
      }
    }
    path = decoded;
  } else if (path.find("://") != std::string::npos) {
    throw Error(fmt::format("resource location {}: only file URIs and folders are read", location));
  }
  if (path.empty()) throw Error("no resource location given: the FMU needs its resources folder");
  return path;
}

void CheckToken(const std::string& resources, const std::string& token) {
  const std::filesystem::path file = std::filesystem::path(resources) / "hybridtest" / "export.json";
  std::ifstream in(file);
  if (!in) throw Error(fmt::format("{} is missing: not the resources of this FMU", file.string()));
  const nlohmann::json j = nlohmann::json::parse(in);
  const std::string expected = j.value("token", "");
  if (token != expected) {
    throw Error(fmt::format("guid / instantiationToken '{}' is not this FMU's ('{}')", token, expected));
  }
}

}  // namespace hybridtest::fmu_export
