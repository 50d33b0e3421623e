// The HDF5 writer is a module (report/hdf5_module.h, apps/hybridtest_hdf5/): the hybridtest
// binary and the layer libraries do not link libhdf5, and a missing or broken module is an
// IoError that says which file and how to get one. (hdf5_export_test.cc checks what it writes.)
#include <elf.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/hdf5_export.h"

namespace hybridtest::report {
namespace {

namespace fs = std::filesystem;

// The string entries with `tag` (DT_NEEDED, DT_RUNPATH, DT_RPATH) of a 64-bit ELF file's
// .dynamic section (names in its sh_link string table), read here rather than by readelf or ldd.
std::vector<std::string> DynamicStrings(const std::string& path, Elf64_Sxword tag) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(fs::file_size(path), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  Elf64_Ehdr header{};
  if (bytes.size() < sizeof header) return {};
  std::memcpy(&header, bytes.data(), sizeof header);
  if (std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0 || header.e_ident[EI_CLASS] != ELFCLASS64) {
    return {};
  }
  const auto section = [&](std::size_t i) {
    Elf64_Shdr s{};
    std::memcpy(&s, bytes.data() + header.e_shoff + i * header.e_shentsize, sizeof s);
    return s;
  };
  std::vector<std::string> needed;
  for (std::size_t i = 0; i < header.e_shnum; ++i) {
    const Elf64_Shdr dynamic = section(i);
    if (dynamic.sh_type != SHT_DYNAMIC) continue;
    const Elf64_Shdr strings = section(dynamic.sh_link);
    for (std::size_t k = 0; k < dynamic.sh_size / sizeof(Elf64_Dyn); ++k) {
      Elf64_Dyn entry{};
      std::memcpy(&entry, bytes.data() + dynamic.sh_offset + k * sizeof entry, sizeof entry);
      if (entry.d_tag == tag) {
        needed.emplace_back(bytes.data() + strings.sh_offset + entry.d_un.d_val);
      }
    }
  }
  return needed;
}

std::vector<std::string> NeededLibraries(const std::string& path) {
  return DynamicStrings(path, DT_NEEDED);
}

std::string Joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += name + " ";
  return text;
}

// The hybridtest binary, and this test program (which links every layer library), load
// libhdf5 only through the module.
TEST(Hdf5Module, NeitherTheBinaryNorTheLibrariesLinkHdf5) {
  for (const std::string& program : {std::string(HYBRIDTEST_BINARY),
                                    fs::read_symlink("/proc/self/exe").string()}) {
    const std::vector<std::string> needed = NeededLibraries(program);
    // The reader works: every program here needs the C library.
    ASSERT_NE(Joined(needed).find("libc.so"), std::string::npos) << program;
    EXPECT_EQ(Joined(needed).find("hdf5"), std::string::npos)
        << program << " needs " << Joined(needed);
  }
}

// No library search path of the binary, the module or this test program has an empty or a
// relative entry, which the loader reads relative to the current directory: CMake's build-tree
// RUNPATH ended with ':' (an empty entry), so a libz.so.1 in the directory hybridtest was started
// from would have been loaded into it.
TEST(Hdf5Module, NoLibrarySearchPathReadsTheCurrentDirectory) {
  for (const std::string& program :
       {std::string(HYBRIDTEST_BINARY), fs::read_symlink("/proc/self/exe").string(),
        (fs::path(HYBRIDTEST_BINARY).parent_path() / "hybridtest_hdf5.so").string()}) {
    ASSERT_FALSE(NeededLibraries(program).empty()) << program;  // the reader works
    for (const Elf64_Sxword tag : {DT_RUNPATH, DT_RPATH}) {
      for (const std::string& path : DynamicStrings(program, tag)) {
        std::size_t begin = 0;
        while (true) {
          const std::size_t end = std::min(path.find(':', begin), path.size());
          const std::string entry = path.substr(begin, end - begin);
          EXPECT_TRUE(!entry.empty() && (entry[0] == '/' || entry.rfind("$ORIGIN", 0) == 0))
              << program << ": search path '" << path << "' has the entry '" << entry << "'";
          if (end == path.size()) break;
          begin = end + 1;
        }
      }
    }
  }
}

// Sets an environment variable for the lifetime of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

std::string ExportError(const std::string& module) {
  const fs::path dir = fs::temp_directory_path() /
                       ("hybridtest_hdf5_module_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "run.csv") << "t\n0\n";
  const io::RunData run = io::LoadRun((dir / "run.csv").string());
  const ScopedEnv env("HYBRIDTEST_HDF5_MODULE", module);
  std::string message;
  try {
    ExportHdf5(run, (dir / "run.h5").string());
  } catch (const IoError& e) {
    message = e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "run.h5"));
  fs::remove_all(dir);
  return message;
}

// HYBRIDTEST_HDF5_MODULE naming a file that is not there: said so, with the two ways out.
TEST(Hdf5Module, NamedModuleThatIsNotThereSaysSoAndHowToFixIt) {
  const std::string module = "/nonexistent/hybridtest/hybridtest_hdf5.so";
  const std::string message = ExportError(module);
  EXPECT_NE(message.find(module), std::string::npos) << message;
  EXPECT_NE(message.find("$HYBRIDTEST_HDF5_MODULE="), std::string::npos) << message;
  EXPECT_NE(message.find("is not a file"), std::string::npos) << message;
  EXPECT_NE(message.find("or unset it"), std::string::npos) << message;
  // Not the hint for a writer that is there but cannot load: libhdf5 is not what is missing.
  EXPECT_EQ(message.find("libhdf5"), std::string::npos) << message;
}

TEST(Hdf5Module, ModuleThatIsNoLibraryIsAClearIoError) {
  const fs::path module = fs::temp_directory_path() /
                          ("hybridtest_hdf5_broken_" + std::to_string(::getpid()) + ".so");
  std::ofstream(module) << "not a shared object\n";
  const std::string message = ExportError(module.string());
  fs::remove(module);
  EXPECT_NE(message.find("cannot load the HDF5 writer " + module.string()), std::string::npos)
      << message;
  EXPECT_NE(message.find("reinstall"), std::string::npos) << message;
}

}  // namespace
}  // namespace hybridtest::report
