// See run_follower.h.
#include "hybridtest/monitor/run_follower.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"

namespace hybridtest::monitor {
namespace {

// The bytes of `path` from `offset` on ("" if there are none).
std::string ReadFrom(const std::string& path, std::uintmax_t offset) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  in.seekg(static_cast<std::streamoff>(offset));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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

// The runner's limits of `slot` from the config text kept in the sidecar, if it has them.
std::optional<transfer::SafetyLimits> LimitsFromConfig(const std::string& config,
                                                       const std::string& slot) {
  try {
    const YAML::Node safety = YAML::Load(config)["substructures"][slot]["safety"];
    if (!safety || !safety.IsMap()) return std::nullopt;
    transfer::SafetyLimits l;
    auto read = [&](const char* key, double& value) {
      if (safety[key]) value = safety[key].as<double>();
    };
    read("stroke_min", l.stroke_min);
    read("stroke_max", l.stroke_max);
    read("max_increment", l.max_increment);
    read("force_soft", l.force_soft);
    read("force_hard", l.force_hard);
    return l;
  } catch (const std::exception&) {
    return std::nullopt;
  }
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

void RunFollower::ReadSidecar() {
  const nlohmann::json sidecar = io::ReadSidecar(csv_);
  if (!described_) {
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
    try {
      const YAML::Node config = YAML::Load(sidecar.value("config", ""));
      if (config["duration"]) id.end_time = config["duration"].as<double>();
      if (config["test"] && config["test"]["specimen"]) {
        id.specimen = YAML::Dump(config["test"]["specimen"]);
      }
    } catch (const std::exception&) {
    }
    std::vector<ActuatorInfo> actuators;
    for (const auto& s : sidecar.value("substructures", nlohmann::json::array())) {
      if (s.value("kind", "") != "physical") continue;
      const std::string slot = s.value("slot", "");
      actuators.push_back({slot, LimitsFromConfig(sidecar.value("config", ""), slot), 0.0});
      id.bench += (id.bench.empty() ? "" : "; ") + s.value("description", slot);
    }
    if (id.bench.empty()) id.bench = "none (numerical)";
    layout_.slots = static_cast<int>(id.slots.size());
    layout_.actuators = static_cast<int>(actuators.size());
    frame_.assign(layout_.width(), std::nan(""));
    state_.SetIdentity(std::move(id), layout_, std::move(actuators));
    described_ = true;
  }
  // Resumes and operator actions appended since the last look.
  const auto& resumes = sidecar.value("resumes", nlohmann::json::array());
  for (; resumes_seen_ < resumes.size(); ++resumes_seen_) {
    state_.AddResume(resumes[resumes_seen_].value("t", 0.0));
  }
  const auto& actions = sidecar.value("operator_actions", nlohmann::json::array());
  for (; actions_seen_ < actions.size(); ++actions_seen_) state_.AddAction(actions[actions_seen_]);
  const std::string status = sidecar.value("status", "running");
  status_ = status;
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
      for (const auto& s : sidecar.value("substructures", nlohmann::json::array())) {
        if (s.value("kind", "") != "physical") continue;
        const std::string slot = s.value("slot", "");
        cmd_col_.push_back(column(slot + "_command"));
        lab_col_.push_back(column(slot + "_lab_time"));
      }
      header_read_ = true;
      continue;
    }
    auto at = [&](int c) { return c >= 0 && c < int(fields.size()) ? ToDouble(fields[c]) : std::nan(""); };
    frame_[0] = static_cast<double>(rows_++);
    frame_[1] = at(0);
    frame_[2] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
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
