// See fmu_instance.h.
#include "hybridtest/fmi/fmu_instance.h"

#include <dlfcn.h>
#include <fmt/core.h>

#include <filesystem>
#include <iostream>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu2_instance.h"
#include "hybridtest/fmi/fmu3_instance.h"

namespace hybridtest::fmi {
namespace {

// The status names shared by FMI 2 and 3 (OK .. Fatal; FMI 2 adds Pending).
const char* StatusName(int s) {
  static const char* names[] = {"OK", "Warning", "Discard", "Error", "Fatal", "Pending"};
  return s >= 0 && s <= 5 ? names[s] : "?";
}

}  // namespace

LogSink StderrLog() {
  return [](const std::string& line) { std::cerr << line << '\n'; };
}

FmuInstance::FmuInstance(const std::string& so, const std::string& binary, std::string fmu,
                         std::string instance_name, LogSink log)
    : fmu_(std::move(fmu)), instance_name_(std::move(instance_name)), log_(std::move(log)) {
  if (!std::filesystem::exists(so)) {
    throw ConfigError(fmt::format("{}: no binary for this platform: {} is missing; export a "
                                  "binary FMU for Linux x86-64", fmu_, binary));
  }
  library_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (library_ == nullptr) {
    throw ConfigError(fmt::format("{}: cannot load {}: {}", fmu_, binary, dlerror()));
  }
}

FmuInstance::~FmuInstance() {
  if (library_ != nullptr) dlclose(library_);
}

void* FmuInstance::Symbol(const char* name, bool required) const {
  void* p = dlsym(library_, name);
  if (p == nullptr && required) {
    throw ConfigError(fmt::format("{}: its binary exports no {} (a co-simulation FMU must "
                                  "export it, or the capability it declares needs it); "
                                  "re-export the FMU with its binary", fmu_, name));
  }
  return p;
}

void FmuInstance::Log(int status, const char* category, const std::string& text) {
  const std::string line = fmt::format("fmu {}: {} [{}] {}", instance_name_, StatusName(status),
                                       category != nullptr ? category : "", text);
  recent_.push_back(line);
  if (recent_.size() > 8) recent_.pop_front();
  if (log_) log_(line);
}

std::string FmuInstance::RecentLines() const {
  std::string lines;
  for (const auto& line : recent_) lines += "\n  " + line;
  return lines;
}

void FmuInstance::Check(int status, const std::string& call) {
  if (status == 0 || status == 1) return;
  if (status == 4) fatal_ = true;
  failed_ = true;
  const std::string lines = RecentLines();
  throw TransferError(fmt::format("{}: {} returned fmi{}{}{}", fmu_, call, fmi_version_,
                                  StatusName(status),
                                  lines.empty() ? " (the FMU logged nothing)"
                                                : "; the FMU's last messages:" + lines));
}

const char* PlatformFolder(const ModelDescription& md) {
  return md.is_fmi3() ? "x86_64-linux" : "linux64";
}

std::unique_ptr<FmuInstance> LoadFmu(const std::string& dir, const ModelDescription& md,
                                     const std::string& fmu, const std::string& instance_name,
                                     LogSink log) {
  if (md.is_fmi3()) return std::make_unique<Fmu3Instance>(dir, md, fmu, instance_name, std::move(log));
  return std::make_unique<Fmu2Instance>(dir, md, fmu, instance_name, std::move(log));
}

}  // namespace hybridtest::fmi
