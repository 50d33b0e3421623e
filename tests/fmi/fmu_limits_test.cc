// The bounds of FMU unpacking (fmu_archive.h): archives made here, small on disk, that would
// take too many members, a highly compressible member (a zip bomb) or a member whose central
// directory declares 4 GiB, each refused with a ConfigError naming the FMU, the member and
// the limit, before the bytes are allocated or written; and a description that declares a
// variable twice. Through the binary: exit 2 (fmu_run_test.cc).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "fmi/fmi_test_support.h"
#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/model_description.h"

namespace hybridtest::fmi {
namespace {

namespace fs = std::filesystem;
using test::TestFmu;

std::string SpringWith(const std::vector<std::pair<std::string, std::string>>& extra,
                       const std::string& name) {
  return test::FmuWith("spring", extra, name);
}

// The message of the ConfigError `f` throws ("" if none).
template <typename F>
std::string Refusal(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(FmuLimits, TooManyMembersAreRefusedBeforeAnythingIsRead) {
  std::vector<std::pair<std::string, std::string>> many;
  for (long long i = 0; i < kMaxFmuMembers; ++i) {
    many.emplace_back("resources/" + std::to_string(i), "");
  }
  const std::string fmu = SpringWith(many, "many.fmu");
  const std::string expected = "more than the limit of 10000 members";
  EXPECT_NE(Refusal([&] { ListMembers(fmu); }).find(expected), std::string::npos);
  const std::string why = Refusal([&] { ExtractArchive(fmu, test_support::FreshTempDir("many")); });
  EXPECT_NE(why.find(expected), std::string::npos) << why;
  EXPECT_NE(why.find("many.fmu"), std::string::npos) << why;
  EXPECT_NE(why.find("docs/fmi.md"), std::string::npos) << why;
}

TEST(FmuLimits, AHighlyCompressibleMemberIsStoppedWhileItStreams) {
  // 8 MiB of zeros compress to some 8 KiB: a small zip bomb.
  const std::string fmu =
      SpringWith({{"resources/zeros.bin", std::string(8u << 20, '\0')}}, "zeros.fmu");
  EXPECT_LT(fs::file_size(fmu), 1u << 20);
  const fs::path into = test_support::FreshTempDir("zeros");
  const std::string why = Refusal([&] { ExtractArchive(fmu, into.string()); });
  EXPECT_NE(why.find("member 'resources/zeros.bin' expands more than 200 times"),
            std::string::npos) << why;
  EXPECT_NE(why.find("limit of the compression ratio is 200"), std::string::npos) << why;
  // Stopped early: not the whole member was written.
  std::error_code ec;
  const auto written = fs::file_size(into / "resources/zeros.bin", ec);
  EXPECT_TRUE(ec || written < (8u << 20)) << written;
  // The same bytes, incompressible enough, pass: the ratio is what is refused.
  std::string noise(2u << 20, '\0');
  std::uint32_t state = 12345;
  for (char& c : noise) {
    state = state * 1664525u + 1013904223u;
    c = static_cast<char>(state >> 24);
  }
  const std::string fine = SpringWith({{"resources/noise.bin", noise}}, "noise.fmu");
  EXPECT_NO_THROW(ExtractArchive(fine, test_support::FreshTempDir("noise").string()));
}

// Sets the uncompressed size of every member named `name` to `size`, in the local header and
// in the central directory (the zip format, APPNOTE 4.3.7 and 4.3.12), as a forged FMU would.
void DeclareSize(const std::string& path, const std::string& name, std::uint32_t size) {
  std::string bytes = test_support::ReadText(path);
  const auto put = [&](std::size_t at) {
    for (std::size_t k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>(size >> (8 * k));
  };
  int patched = 0;
  for (std::size_t at = 0; (at = bytes.find("PK", at)) != std::string::npos; ++at) {
    const bool local = bytes.compare(at, 4, std::string("PK\x03\x04", 4)) == 0;
    const bool central = bytes.compare(at, 4, std::string("PK\x01\x02", 4)) == 0;
    const std::size_t name_at = at + (local ? 30 : 46);
    if ((local || central) && bytes.compare(name_at, name.size(), name) == 0) {
      put(at + (local ? 22 : 24));
      ++patched;
    }
  }
  ASSERT_EQ(patched, 2);
  test_support::WriteText(path, bytes);
}

TEST(FmuLimits, AMemberDeclaringFourGibibytesIsRefusedWithoutAllocating) {
  const std::string fmu =
      SpringWith({{"resources/big.bin", std::string(4096, 'a')}}, "declares.fmu");
  DeclareSize(fmu, "resources/big.bin", 0xFFFFFFF0u);
  const std::string why = Refusal([&] { ReadMember(fmu, "resources/big.bin"); });
  EXPECT_NE(why.find("member 'resources/big.bin' declares 4294967280 bytes unpacked, more than "
                     "the limit of 1073741824 bytes for one member"), std::string::npos) << why;
  EXPECT_NE(why.find("declares.fmu"), std::string::npos) << why;
  EXPECT_NE(Refusal([&] { ExtractArchive(fmu, test_support::FreshTempDir("declares")); })
                .find("declares 4294967280 bytes"),
            std::string::npos);
}

TEST(FmuLimits, AVariableDeclaredTwiceIsRefusedWithBothLines) {
  const std::string fmu = test::EditedFmu("spring", R"(<ScalarVariable name="k")",
                                          R"(<ScalarVariable name="x")", "twice.fmu");
  const std::string xml = ReadMember(fmu, "modelDescription.xml");
  const std::string why = Refusal([&] { ParseModelDescription(xml, fmu); });
  EXPECT_NE(why.find("variable 'x' is declared twice (lines 12 and 16)"), std::string::npos)
      << why;
  EXPECT_NE(why.find("twice.fmu: modelDescription.xml:16:"), std::string::npos) << why;
}

}  // namespace
}  // namespace hybridtest::fmi
