// Figures of one run: valid, non-trivial images with the titles, labels and highlighting.
#include "hybridtest/report/plot.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "hybridtest/report/plot_layout.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Width and height from a PNG's IHDR chunk; {0, 0} when the signature or IHDR is wrong.
std::pair<std::uint32_t, std::uint32_t> PngSize(const std::string& bytes) {
  const std::string signature = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 24 || bytes.compare(0, 8, signature) != 0 ||
      bytes.compare(12, 4, "IHDR") != 0) {
    return {0, 0};
  }
  auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  return {be32(16), be32(20)};
}

std::string Find(const std::vector<std::string>& files, const std::string& name) {
  for (const std::string& f : files) {
    if (std::filesystem::path(f).filename() == name) return f;
  }
  return "";
}

TEST(WritePlots, RotorWithPhysicalBladeWritesFigure6LikeImages) {
  const std::string dir = testing::FreshDir("plot-rotor");
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir, {}));
  const auto files = WritePlots(run, dir + "/fig");
  for (const char* name : {"displacements.png", "displacements.svg", "hub-speed.png",
                           "hub-speed.svg", "r1-command-position.png", "r1-command-position.svg",
                           "r1-force-displacement.png", "r1-force-displacement.svg"}) {
    SCOPED_TRACE(name);
    const std::string path = Find(files, name);
    ASSERT_FALSE(path.empty());
    const std::string bytes = Slurp(path);
    EXPECT_GT(bytes.size(), 5000u);
    if (path.ends_with(".png")) {
      const auto [w, h] = PngSize(bytes);
      EXPECT_EQ(w, 1000u);
      EXPECT_GT(h, 300u);
    } else {
      EXPECT_EQ(bytes.find("<?xml"), 0u);
      EXPECT_NE(bytes.find("<svg"), std::string::npos);
      EXPECT_NE(bytes.find("</svg>"), std::string::npos);
      if (path.find("force-displacement") == std::string::npos) {
        EXPECT_NE(bytes.find("time t [s]"), std::string::npos);
      }
    }
  }
  // Fig. 6a: title, units, and the physical blade in red with its own legend entry.
  const std::string svg = Slurp(Find(files, "displacements.svg"));
  EXPECT_NE(svg.find("Blade-tip displacements q1..q3 (run hybrid)"), std::string::npos);
  EXPECT_NE(svg.find("blade-tip displacement [m]"), std::string::npos);
  EXPECT_NE(svg.find("q1 (physical, r1)"), std::string::npos);
  EXPECT_NE(svg.find("rgb(214,  39,  40)"), std::string::npos);
  EXPECT_NE(svg.find(">q2<"), std::string::npos);
  // Fig. 6b: the hub speed u4 only.
  const std::string hub = Slurp(Find(files, "hub-speed.svg"));
  EXPECT_NE(hub.find("hub angular speed u4 [rad/s]"), std::string::npos);
  EXPECT_EQ(hub.find(">u1<"), std::string::npos);
  // Hysteresis: force against displacement, with units.
  const std::string loop = Slurp(Find(files, "r1-force-displacement.svg"));
  EXPECT_NE(loop.find("measured restoring force r1_force [N]"), std::string::npos);
  EXPECT_NE(loop.find("measured position r1_position [m]"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::report
