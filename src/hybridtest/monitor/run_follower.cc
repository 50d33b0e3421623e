// See run_follower.h.
#include "hybridtest/monitor/run_follower.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <ctime>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/limit_use.h"

namespace hybridtest::monitor {
namespace {

// The bytes of `path` from `offset` on ("" if there are none).
// (Read into a sized string: GCC 12 warns -Wnull-dereference inside istreambuf_iterator.)
std::string ReadFrom(const std::string& path, std::uintmax_t offset) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  std::ifstream in(path, std::ios::binary);
  if (error || !in || size <= offset) return {};
  in.seekg(static_cast<std::streamoff>(offset));
  std::string text(static_cast<std::size_t>(size - offset), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text;
}

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

double ToDouble(const std::string& text) {
  try {
    return std::stod(text);
  } catch (const std::exception&) {
    return std::nan("");
  }
}

// Actuator k's p0 [m] of `substructure` from the config text kept in the sidecar
// (`setup.p0`: one value, or one per actuator), if it has one.
std::optional<double> P0FromConfig(const YAML::Node& config, const std::string& substructure,
                                   int k) {
  try {
    const YAML::Node p0 = config["substructures"][substructure]["setup"]["p0"];
    if (p0 && p0.IsScalar()) return p0.as<double>();
    if (p0 && p0.IsSequence() && k < static_cast<int>(p0.size())) return p0[k].as<double>();
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// "2026-11-27T10:16:10Z" as seconds since the epoch (nullopt if it is not that).
std::optional<double> ParseUtc(const std::string& text) {
  std::tm tm{};
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2dZ", &tm.tm_year, &tm.tm_mon, &tm.tm_mday,
                  &tm.tm_hour, &tm.tm_min, &tm.tm_sec) != 6) {
    return std::nullopt;
  }
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  return static_cast<double>(timegm(&tm));
}

}  // namespace

RunFollower::RunFollower(std::string csv_path, MonitorState& state)
    : csv_(std::move(csv_path)), state_(state), start_(std::chrono::steady_clock::now()) {
  if (!std::filesystem::is_regular_file(csv_)) {
    throw IoError(fmt::format("{}: no such journal: give the CSV of a run (its .meta.json "
                              "beside it)", csv_));
  }
  ReadSidecar();
}

bool RunFollower::Poll() {
  CountStages();  // first: the rows read next carry the evaluations up to them
  ReadRows();
  ReadSidecar();
  return status_ == "running";
}

void RunFollower::Describe(const nlohmann::json& sidecar) {
  RunIdentity id;
  id.mode = "follow";
  id.config = sidecar.value("config_path", "");
  id.command = sidecar.value("command", "");
  id.csv = csv_;
  const nlohmann::json& model = sidecar.value("model", nlohmann::json::object());
  id.model = model.value("name", "");
  for (const auto& s : model.value("slots", nlohmann::json::array())) {
    id.slots.push_back(s.value("name", ""));
  }
  YAML::Node config;
  try {
    config = YAML::Load(sidecar.value("config", ""));
    if (config["duration"]) id.end_time = config["duration"].as<double>();
    if (config["test"] && config["test"]["specimen"]) {
      id.specimen = YAML::Dump(config["test"]["specimen"]);
    }
    if (config["real_time"]) {
      // A paced run: its statistics are the sidecar's, once it has ended.
      id.real_time.enabled = true;
      id.real_time.tick = config["integrator"]["dt"].as<double>(0.0);
      id.real_time.hold_after_misses = config["real_time"]["hold_after_misses"].as<long>(10);
      id.real_time.live = false;
    }
  } catch (const std::exception&) {
  }
  // Every actuator of every physical substructure, as its journal channels name it; its
  // limits and p0 from the config the run recorded.
  io::RunData run;
  run.metadata = sidecar;
  std::vector<ActuatorInfo> actuators;
  for (const auto& s : sidecar.value("substructures", nlohmann::json::array())) {
    if (s.value("kind", "") != "physical") continue;
    const std::string name = s.value("slot", "");
    std::vector<std::string> slots = s.value("slots", std::vector<std::string>{});
    if (slots.empty()) slots = {name};
    const nlohmann::json groups = s.value("channels", nlohmann::json::array());
    const bool several = groups.is_array() && !groups.empty();
    const int n = several ? static_cast<int>(groups.size()) : 1;
    for (int k = 0; k < n; ++k) {
      const std::string command =
          several ? groups[std::size_t(k)].value("command", "") : name + "_command";
      const std::string prefix =
          command.ends_with("_command") ? command.substr(0, command.size() - 8) : command;
      actuators.push_back({prefix, name, k, slots,
                           report::FindActuatorLimits(run, name, several ? k : -1),
                           P0FromConfig(config, name, k)});
      channels_.push_back({prefix + "_command", prefix + "_lab_time"});
    }
    id.bench += (id.bench.empty() ? "" : "; ") + s.value("description", name);
  }
  if (id.bench.empty()) id.bench = "none (numerical)";
  if (const auto start = ParseUtc(sidecar.value("start_time", ""))) started_ = *start;
  layout_.slots = static_cast<int>(id.slots.size());
  layout_.actuators = static_cast<int>(actuators.size());
  layout_ = state_.SetIdentity(std::move(id), layout_, std::move(actuators));
  frame_.assign(layout_.width(), std::nan(""));
  described_ = true;
}

void RunFollower::ReadSidecar() {
  const nlohmann::json sidecar = io::ReadSidecar(csv_);
  if (!described_) Describe(sidecar);
  // Resumes and operator actions appended since the last look.
  const auto& resumes = sidecar.value("resumes", nlohmann::json::array());
  for (; resumes_seen_ < resumes.size(); ++resumes_seen_) {
    state_.AddResume(resumes[resumes_seen_].value("t", 0.0));
  }
  const auto& actions = sidecar.value("operator_actions", nlohmann::json::array());
  for (; actions_seen_ < actions.size(); ++actions_seen_) state_.AddAction(actions[actions_seen_]);
  const std::string status = sidecar.value("status", "running");
  status_ = status;
  // A run that has ended: its elapsed, lab time and evaluations as it recorded them, and
  // its real-time statistics.
  const nlohmann::json& stats = sidecar.value("statistics", nlohmann::json::object());
  if (status != "running" && stats.is_object()) {
    RecordedTotals totals;
    if (stats.contains("wall_time_s")) totals.wall_time = stats["wall_time_s"].get<double>();
    if (stats.contains("lab_time_s")) totals.lab_time = stats["lab_time_s"].get<double>();
    if (stats.contains("physical_evaluations")) {
      totals.physical_evaluations = stats["physical_evaluations"].get<long>();
    }
    state_.SetRecorded(totals);
    if (stats.contains("real_time")) state_.SetRealTime(stats["real_time"]);
  }
  if (status == "completed") {
    state_.SetStatus("finished");
  } else if (status.rfind("stopped", 0) == 0) {
    const auto& stop = sidecar.value("statistics", nlohmann::json::object())
                           .value("stop", nlohmann::json::object());
    state_.SetStatus("stopped", status.size() > 9 ? status.substr(9) : std::string(),
                     fmt::format("hybridtest resume {}{}", csv_,
                                 stop.value("kind", "") == "safety" ? " --after-safety-stop" : ""));
  } else if (rows_ > 0) {
    state_.SetStatus("running");
  }
}

void RunFollower::ReadRows() {
  const std::string text = ReadFrom(csv_, offset_);
  offset_ += text.size();
  partial_ += text;
  std::size_t start = 0;
  for (std::size_t eol; (eol = partial_.find('\n', start)) != std::string::npos; start = eol + 1) {
    const std::vector<std::string> fields = Split(partial_.substr(start, eol - start));
    if (!header_read_) {
      // The columns of r (the slots' names) and of each physical slot's channels.
      auto column = [&](const std::string& name) {
        for (std::size_t i = 0; i < fields.size(); ++i) {
          if (fields[i] == name) return static_cast<int>(i);
        }
        return -1;
      };
      const nlohmann::json sidecar = io::ReadSidecar(csv_);
      for (const auto& s : sidecar.value("model", nlohmann::json::object())
                               .value("slots", nlohmann::json::array())) {
        r_col_.push_back(column(s.value("name", "")));
      }
      for (const auto& [command, lab] : channels_) {
        cmd_col_.push_back(column(command));
        lab_col_.push_back(column(lab));
      }
      header_read_ = true;
      continue;
    }
    auto at = [&](int c) { return c >= 0 && c < int(fields.size()) ? ToDouble(fields[c]) : std::nan(""); };
    frame_[0] = static_cast<double>(rows_++);
    frame_[1] = at(0);
    frame_[2] = Elapsed();
    double lab = 0.0;
    for (int c : lab_col_) {
      if (std::isfinite(at(c))) lab = std::max(lab, at(c));
    }
    frame_[3] = lab;
    frame_[4] = static_cast<double>(evaluations_);
    for (int s = 0; s < layout_.slots && s < int(r_col_.size()); ++s) {
      frame_[layout_.d(s)] = std::nan("");
      frame_[layout_.r(s)] = at(r_col_[std::size_t(s)]);
    }
    for (int a = 0; a < layout_.actuators && a < int(cmd_col_.size()); ++a) {
      const int c = cmd_col_[std::size_t(a)];
      frame_[layout_.command(a)] = at(c);
      frame_[layout_.position(a)] = at(c < 0 ? -1 : c + 1);
      frame_[layout_.force(a)] = at(c < 0 ? -1 : c + 2);
    }
    state_.AddFrame(frame_);
  }
  partial_.erase(0, start);
}

double RunFollower::Elapsed() const {
  if (started_) {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
               .count() - *started_;
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void RunFollower::CountStages() {
  const std::string path = io::StagesPath(csv_);
  if (!std::filesystem::is_regular_file(path)) return;
  const std::string text = ReadFrom(path, stages_offset_);
  // Whole lines only; the header is not an evaluation.
  const std::size_t last = text.rfind('\n');
  if (last == std::string::npos) return;
  const long lines = static_cast<long>(std::count(text.begin(), text.begin() + long(last) + 1, '\n'));
  evaluations_ += stages_offset_ == 0 ? lines - 1 : lines;
  stages_offset_ += last + 1;
}

}  // namespace hybridtest::monitor
