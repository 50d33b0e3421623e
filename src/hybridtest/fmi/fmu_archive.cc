// See fmu_archive.h.
#include "hybridtest/fmi/fmu_archive.h"

#include <fmt/core.h>
#include <zip.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

struct ArchiveCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
using Archive = std::unique_ptr<zip_t, ArchiveCloser>;

Archive OpenForReading(const std::string& fmu) {
  int error = 0;
  zip_t* z = zip_open(fmu.c_str(), ZIP_RDONLY, &error);
  if (z == nullptr) {
    zip_error_t e;
    zip_error_init_with_code(&e, error);
    std::string why = zip_error_strerror(&e);
    zip_error_fini(&e);
    throw ConfigError(fmt::format("{}: cannot open the FMU ({}); expected a zip archive with "
                                  "modelDescription.xml at its root", fmu, why));
  }
  return Archive(z);
}

std::string ReadIndex(zip_t* z, zip_uint64_t index, const std::string& fmu,
                      const std::string& name) {
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat_index(z, index, 0, &st) != 0 || (st.valid & ZIP_STAT_SIZE) == 0) {
    throw ConfigError(fmt::format("{}: cannot read the size of member {}", fmu, name));
  }
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> file(zip_fopen_index(z, index, 0),
                                                         &zip_fclose);
  if (!file) {
    throw ConfigError(fmt::format("{}: cannot open member {} ({})", fmu, name, zip_strerror(z)));
  }
  std::string bytes(static_cast<std::size_t>(st.size), '\0');
  const zip_int64_t got = zip_fread(file.get(), bytes.data(), st.size);
  if (got < 0 || static_cast<zip_uint64_t>(got) != st.size) {
    throw ConfigError(fmt::format("{}: member {} is truncated or corrupt", fmu, name));
  }
  return bytes;
}

}  // namespace

std::vector<std::string> ListMembers(const std::string& fmu) {
  Archive z = OpenForReading(fmu);
  std::vector<std::string> names;
  const zip_int64_t n = zip_get_num_entries(z.get(), 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(z.get(), static_cast<zip_uint64_t>(i), 0);
    if (name != nullptr) names.emplace_back(name);
  }
  return names;
}

std::string ReadMember(const std::string& fmu, const std::string& name) {
  Archive z = OpenForReading(fmu);
  const zip_int64_t index = zip_name_locate(z.get(), name.c_str(), 0);
  if (index < 0) {
    throw ConfigError(fmt::format("{}: the FMU has no {} (an FMU holds modelDescription.xml at "
                                  "its root and binaries/<platform>/<modelIdentifier>.so)",
                                  fmu, name));
  }
  return ReadIndex(z.get(), static_cast<zip_uint64_t>(index), fmu, name);
}

void ExtractArchive(const std::string& fmu, const std::string& dir) {
  namespace fs = std::filesystem;
  Archive z = OpenForReading(fmu);
  fs::create_directories(dir);
  const zip_int64_t n = zip_get_num_entries(z.get(), 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* raw = zip_get_name(z.get(), static_cast<zip_uint64_t>(i), 0);
    if (raw == nullptr) continue;
    const std::string name = raw;
    const fs::path rel = fs::path(name).lexically_normal();
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..") {
      throw ConfigError(fmt::format("{}: member '{}' would be written outside the folder it is "
                                    "unpacked into; the FMU is refused", fmu, name));
    }
    const fs::path target = fs::path(dir) / rel;
    if (!name.empty() && name.back() == '/') {
      fs::create_directories(target);
      continue;
    }
    fs::create_directories(target.parent_path());
    const std::string bytes = ReadIndex(z.get(), static_cast<zip_uint64_t>(i), fmu, name);
    std::ofstream out(target, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw IoError(fmt::format("{}: cannot write {}", fmu, target.string()));
  }
}

void WriteArchive(const std::string& path,
                  const std::vector<std::pair<std::string, std::string>>& members) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  int error = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (z == nullptr) throw IoError(fmt::format("{}: cannot create the archive", path));
  Archive guard(z);
  for (const auto& [name, bytes] : members) {
    // libzip reads the buffer at zip_close: `members` outlives it.
    zip_source_t* src = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
    if (src == nullptr || zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE) < 0) {
      if (src != nullptr) zip_source_free(src);
      throw IoError(fmt::format("{}: cannot add {} ({})", path, name, zip_strerror(z)));
    }
  }
  zip_t* done = guard.release();
  if (zip_close(done) != 0) {
    const std::string why = zip_strerror(done);
    zip_discard(done);
    throw IoError(fmt::format("{}: cannot write the archive ({})", path, why));
  }
}

std::string MakeUnpackDir() {
  const std::string pattern =
      (std::filesystem::temp_directory_path() / "hybridtest-fmu-XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (mkdtemp(buffer.data()) == nullptr) {
    throw IoError(fmt::format("cannot create a folder to unpack an FMU in ({})", pattern));
  }
  return buffer.data();
}

std::string ToHex(const std::string& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (unsigned char c : bytes) {
    out.push_back(digits[c >> 4]);
    out.push_back(digits[c & 15]);
  }
  return out;
}

std::string FromHex(const std::string& hex) {
  if (hex.size() % 2 != 0) throw Error("FMU state: odd number of hex digits");
  std::string out(hex.size() / 2, '\0');
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
  }
  return out;
}

}  // namespace hybridtest::fmi
