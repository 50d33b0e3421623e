#pragma once
// Synthetic runs for the report tests, written directly in the journal format (CSV with a
// names line and 17 significant digits, plus the JSON sidecar beside it), so the tests read
// them back through io::LoadRun like any real run.
#include <Eigen/Core>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hybridtest/io/journal.h"

namespace hybridtest::report::testing {

// A fresh, empty directory under the system temp directory, unique per test and process,
// removed at the end of the test unless HYBRIDTEST_KEEP_TEST_FILES is set (to look at the
// figures).
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_((std::filesystem::temp_directory_path() /
               fmt::format("hybridtest-report-test-{}-{}", name, ::getpid()))
                  .string()) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    if (std::getenv("HYBRIDTEST_KEEP_TEST_FILES") == nullptr) {
      std::error_code ignored;
      std::filesystem::remove_all(path_, ignored);
    }
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

inline std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes csv_path (and, if metadata is an object, its sidecar).
inline void WriteRunFiles(const std::string& csv_path, const std::vector<io::Channel>& channels,
                          const Eigen::MatrixXd& values, const nlohmann::json& metadata) {
  std::ofstream csv(csv_path);
  for (std::size_t c = 0; c < channels.size(); ++c) csv << (c ? "," : "") << channels[c].name;
  csv << "\n";
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      csv << (c ? "," : "") << fmt::format("{:.17g}", values(r, c));
    }
    csv << "\n";
  }
  if (!metadata.is_object()) return;
  nlohmann::json meta = metadata;
  meta["channels"] = nlohmann::json::array();
  for (const io::Channel& ch : channels) {
    meta["channels"].push_back({{"name", ch.name}, {"unit", ch.unit},
                                {"description", ch.description}});
  }
  std::ofstream(io::SidecarPath(csv_path)) << meta.dump(2);
}

struct RotorRunSpec {
  std::string name = "hybrid";
  int rows = 2001;
  double dt = 0.005;                  // [s]
  bool physical_r1 = true;            // r1 is a physical substructure
  bool sidecar = true;
  double q1_offset = 0.02;            // [m] extra mean of q1 (the softer physical blade)
  std::string config = "model: rotor\nintegrator: {method: rk2, dt: 0.001}\n";
};

// A 3-blade rotor-like run: q1..q3 = mean + decaying transient + sine, q4 the hub angle,
// u = derivatives, r = k q, and (if r1 is physical) r1_command/position/force/lab_time.
inline std::string WriteRotorRun(const std::string& dir, const RotorRunSpec& spec) {
  std::vector<io::Channel> ch{{"t", "s", "time"}};
  for (int i = 1; i <= 4; ++i) {
    ch.push_back({fmt::format("q{}", i), i < 4 ? "m" : "rad",
                  i < 4 ? fmt::format("tip deflection of blade {}", i) : "hub rotation"});
  }
  for (int i = 1; i <= 4; ++i) {
    ch.push_back({fmt::format("u{}", i), i < 4 ? "m/s" : "rad/s",
                  i < 4 ? fmt::format("tip speed of blade {}", i) : "hub angular speed"});
  }
  for (int i = 1; i <= 3; ++i) ch.push_back({fmt::format("r{}", i), "N", "restoring force"});
  if (spec.physical_r1) {
    ch.push_back({"r1_command", "m", "actuator command"});
    ch.push_back({"r1_position", "m", "measured actuator position"});
    ch.push_back({"r1_force", "N", "measured force"});
    ch.push_back({"r1_lab_time", "s", "lab time"});
  }
  Eigen::MatrixXd v(spec.rows, static_cast<Eigen::Index>(ch.size()));
  const double w = 1.5;  // [rad/s]
  for (int r = 0; r < spec.rows; ++r) {
    const double t = r * spec.dt;
    const double ramp = 1.0 - std::exp(-t / 0.5);
    v(r, 0) = t;
    for (int i = 0; i < 3; ++i) {
      const double phase = w * t + 2.0 * M_PI * i / 3.0;
      const double mean = 0.05 + (i == 0 ? spec.q1_offset : 0.0);
      v(r, 1 + i) = ramp * (mean + 0.03 * std::sin(phase));
      v(r, 5 + i) = 0.03 * w * std::cos(phase);
      v(r, 9 + i) = 7200.0 * v(r, 1 + i);
    }
    v(r, 4) = 1.5 * t;
    v(r, 8) = 1.5 * ramp + 0.01 * std::sin(w * t);
    if (spec.physical_r1) {
      v(r, 12) = v(r, 1) + 0.1;
      v(r, 13) = v(r, 1) + 0.1 + 1e-4 * std::sin(40 * t);
      v(r, 14) = 5250.0 * v(r, 1) + 20.0 * std::cos(w * t);
      v(r, 15) = 1.13 * 2 * r;
    }
  }
  nlohmann::json meta;
  if (spec.sidecar) {
    meta = {{"config", spec.config},
            {"status", "completed"},
            {"model",
             {{"name", "rotor"},
              {"parameters",
               {{{"name", "m_b"}, {"value", 50.0}, {"unit", "kg"}, {"description", "tip mass"}},
                {{"name", "k_b"}, {"value", 7200.0}, {"unit", "N/m"},
                 {"description", "blade <stiffness> & more"}}}},
              {"slots",
               {{{"name", "r1"}, {"coordinate", "q1"}, {"description", "blade 1"}},
                {{"name", "r2"}, {"coordinate", "q2"}, {"description", "blade 2"}},
                {{"name", "r3"}, {"coordinate", "q3"}, {"description", "blade 3"}}}}}},
            {"statistics",
             {{"steps", spec.rows - 1}, {"physical_evaluations", spec.physical_r1 ? 2 * (spec.rows - 1) : 0},
              {"wall_time_s", 22560.0}, {"lab_time_s", 22600.0}, {"slowdown", 2260.0}}}};
    meta["substructures"] = nlohmann::json::array();
    for (int i = 1; i <= 3; ++i) {
      const bool phys = spec.physical_r1 && i == 1;
      nlohmann::json s = {{"slot", fmt::format("r{}", i)},
                          {"kind", phys ? "physical" : "numerical"},
                          {"description", phys ? "steel cantilever on the bench" : "k_b q"}};
      if (phys) {
        s["channels"] = {{"command", "r1_command"}, {"position", "r1_position"},
                         {"force", "r1_force"}, {"lab_time", "r1_lab_time"}};
      }
      meta["substructures"].push_back(s);
    }
  }
  const std::string path = (std::filesystem::path(dir) / (spec.name + ".csv")).string();
  WriteRunFiles(path, ch, v, meta);
  return path;
}

}  // namespace hybridtest::report::testing
