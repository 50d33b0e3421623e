#pragma once
// The test FMUs built by tests/fmi/CMakeLists.txt, variants of them written on the fly (a
// description edited, a member left out), and FMU substructures made from a config snippet.
#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/fmu_config.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "support/temp_dir.h"

namespace hybridtest::fmi::test {

inline std::string TestFmu(const std::string& id) {
  return fmt::format("{}/{}.fmu", HYBRIDTEST_TEST_FMU_DIR, id);
}

// A copy of the built FMU `id` whose description went through `edit` (first occurrence of
// `from` replaced by `to`); `keep_binary` false leaves the binary out.
inline std::string EditedFmu(const std::string& id, const std::string& from,
                             const std::string& to, const std::string& out_name,
                             bool keep_binary = true) {
  const std::string fmu = TestFmu(id);
  std::string xml = ReadMember(fmu, "modelDescription.xml");
  if (!from.empty()) {
    const auto at = xml.find(from);
    if (at == std::string::npos) throw std::runtime_error("EditedFmu: no '" + from + "'");
    xml.replace(at, from.size(), to);
  }
  std::vector<std::pair<std::string, std::string>> members{{"modelDescription.xml", xml}};
  for (const auto& member : ListMembers(fmu)) {  // the binary, whatever its platform
    if (keep_binary && member.rfind("binaries/", 0) == 0 && member.back() != '/') {
      members.emplace_back(member, ReadMember(fmu, member));
    }
  }
  static const auto dir = test_support::FreshTempDir("fmi_variants");
  const std::string path = (dir / out_name).string();
  WriteArchive(path, members);
  return path;
}

// A copy of the built FMU `id` (description and binary) with the members `extra` added,
// written at `out_name` (a zip bomb, a forged member).
inline std::string FmuWith(const std::string& id,
                           const std::vector<std::pair<std::string, std::string>>& extra,
                           const std::string& out_name) {
  const std::string fmu = TestFmu(id);
  const std::string so = "binaries/linux64/" + id + ".so";
  std::vector<std::pair<std::string, std::string>> members{
      {"modelDescription.xml", ReadMember(fmu, "modelDescription.xml")}, {so, ReadMember(fmu, so)}};
  members.insert(members.end(), extra.begin(), extra.end());
  static const auto dir = test_support::FreshTempDir("fmi_with");
  const std::string path = (dir / out_name).string();
  WriteArchive(path, members);
  return path;
}

// The spec of `type: fmu` read from `yaml` (the substructure's mapping), slot "r1" or
// `slots`.
inline substructures::SubstructureSpec FmuSpec(const std::string& yaml,
                                               std::vector<std::string> slots = {"r1"}) {
  const YamlInput in = YamlInput::FromText(yaml, "test.yaml");
  const std::string name = slots.size() == 1 ? slots[0] : "block";
  return ParseFmuSubstructure(in, in.root(), name, slots, "substructures." + name, nullptr);
}

}  // namespace hybridtest::fmi::test
