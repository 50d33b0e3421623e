// hybridtest_pack_fmu: zips an FMU at build time (examples/fmi/ and tests/fmi/CMakeLists.txt).
//   hybridtest_pack_fmu OUT.fmu modelDescription.xml [MEMBER=FILE ...]
// The description becomes modelDescription.xml at the root; each MEMBER (e.g.
// binaries/linux64/spring.so) gets the bytes of FILE.
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"

namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw hybridtest::IoError("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: hybridtest_pack_fmu OUT.fmu modelDescription.xml [MEMBER=FILE ...]\n";
    return 2;
  }
  try {
    std::vector<std::pair<std::string, std::string>> members{
        {"modelDescription.xml", Slurp(argv[2])}};
    for (int i = 3; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto eq = arg.find('=');
      if (eq == std::string::npos) throw hybridtest::Error("expected MEMBER=FILE, got " + arg);
      members.emplace_back(arg.substr(0, eq), Slurp(arg.substr(eq + 1)));
    }
    hybridtest::fmi::WriteArchive(argv[1], members);
  } catch (const std::exception& e) {
    std::cerr << "hybridtest_pack_fmu: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
