// See fmu_archive.h.
#include "hybridtest/fmi/fmu_archive.h"

#include <fmt/core.h>
#include <zip.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

struct ArchiveCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
using Archive = std::unique_ptr<zip_t, ArchiveCloser>;

// The refusal of an archive that breaks a limit (fmu_archive.h): what, where, and the way on.
[[noreturn]] void Refuse(const std::string& fmu, const std::string& what) {
  throw ConfigError(fmt::format(
      "{}: {}; the FMU is refused (limits of FMU unpacking: docs/fmi.md, \"Limits\"). An FMU "
      "of a model is a few megabytes: re-export it from its tool, and look at what it holds "
      "with `unzip -lv` before using it", fmu, what));
}

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
  Archive archive(z);
  const zip_int64_t n = zip_get_num_entries(z, 0);
  if (n > kMaxFmuMembers) {
    Refuse(fmu, fmt::format("the archive holds {} members, more than the limit of {} members",
                            n, kMaxFmuMembers));
  }
  return archive;
}

// Streams member `index` (named `name`) to `sink` in chunks, counting its bytes against the
// limits as they come; *total counts the archive's unpacked bytes so far. The declared size
// is checked first and never allocated.
void StreamIndex(zip_t* z, zip_uint64_t index, const std::string& fmu, const std::string& name,
                 long long* total, const std::function<void(const char*, std::size_t)>& sink) {
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat_index(z, index, 0, &st) != 0 || (st.valid & ZIP_STAT_SIZE) == 0) {
    throw ConfigError(fmt::format("{}: cannot read the size of member {}", fmu, name));
  }
  if (st.size > static_cast<zip_uint64_t>(kMaxFmuMemberBytes)) {
    Refuse(fmu, fmt::format("member '{}' declares {} bytes unpacked, more than the limit of {} "
                            "bytes for one member", name, st.size, kMaxFmuMemberBytes));
  }
  const long long compressed =
      (st.valid & ZIP_STAT_COMP_SIZE) != 0 ? static_cast<long long>(st.comp_size) : 0;
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> file(zip_fopen_index(z, index, 0),
                                                         &zip_fclose);
  if (!file) {
    throw ConfigError(fmt::format("{}: cannot open member {} ({})", fmu, name, zip_strerror(z)));
  }
  std::vector<char> chunk(64 * 1024);
  long long got = 0;
  for (;;) {
    const zip_int64_t n = zip_fread(file.get(), chunk.data(), chunk.size());
    if (n < 0) {
      throw ConfigError(fmt::format("{}: member {} is truncated or corrupt ({})", fmu, name,
                                    zip_file_strerror(file.get())));
    }
    if (n == 0) break;
    got += n;
    *total += n;
    // Counted as read, whatever the archive declared.
    if (got > kMaxFmuMemberBytes) {
      Refuse(fmu, fmt::format("member '{}' unpacks to more than the limit of {} bytes for one "
                              "member", name, kMaxFmuMemberBytes));
    }
    if (*total > kMaxFmuTotalBytes) {
      Refuse(fmu, fmt::format("member '{}' takes the unpacked archive past the limit of {} bytes "
                              "in all", name, kMaxFmuTotalBytes));
    }
    if (got > kFmuRatioFloorBytes && got > kMaxFmuRatio * std::max(compressed, 1LL)) {
      Refuse(fmu, fmt::format("member '{}' expands more than {} times ({} compressed bytes gave "
                              "{} bytes so far; the limit of the compression ratio "
                              "is {} for a member above {} bytes): a zip bomb", name,
                              kMaxFmuRatio, compressed, got, kMaxFmuRatio, kFmuRatioFloorBytes));
    }
    sink(chunk.data(), static_cast<std::size_t>(n));
  }
  if (static_cast<zip_uint64_t>(got) != st.size) {
    throw ConfigError(fmt::format("{}: member {} is truncated or corrupt (it declares {} bytes "
                                  "and holds {})", fmu, name, st.size, got));
  }
}

std::string ReadIndex(zip_t* z, zip_uint64_t index, const std::string& fmu,
                      const std::string& name) {
  std::string bytes;
  long long total = 0;
  StreamIndex(z, index, fmu, name, &total,
              [&bytes](const char* data, std::size_t n) { bytes.append(data, n); });
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
  long long total = 0;  // unpacked bytes so far [bytes]
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
    std::ofstream out(target, std::ios::binary | std::ios::trunc);
    StreamIndex(z.get(), static_cast<zip_uint64_t>(i), fmu, name, &total,
                [&out](const char* data, std::size_t size) {
                  out.write(data, static_cast<std::streamsize>(size));
                });
    if (!out.flush()) throw IoError(fmt::format("{}: cannot write {}", fmu, target.string()));
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
