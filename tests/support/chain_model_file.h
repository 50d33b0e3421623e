#pragma once
// A model file for a planar chain of n links (tests and bench/): link k is the frame L_k,
// turned about ẑ by q_k relative to L_{k−1} (L_0 = N); its tip P_k = P_{k−1} + l l̂_kx carries a
// point mass m; gravity m g n̂_x acts at every tip. The first `slots` joints have a rotational
// restoring-force slot r_k [N·m] seeing q_k, acting as −r_k ẑ on L_k and +r_k ẑ on L_{k−1}.
// Every field is affine: the engine's fast path, no jets, no coordinate cap.
#include <fmt/core.h>

#include <string>

namespace hybridtest::test_support {

inline std::string ChainModelFile(int n, int slots) {
  std::string s = fmt::format(
      "name: chain{}\nparameters:\n  m: {{value: 0.5, unit: kg}}\n  l: {{value: 0.3, unit: m}}\n"
      "  g: {{value: 9.81, unit: m/s²}}\n  k: {{value: 40, unit: N·m/rad}}\ncoordinates:\n", n);
  for (int k = 1; k <= n; ++k) s += fmt::format("  - {{name: q{}, unit: rad}}\n", k);
  s += "frames:\n";
  for (int k = 1; k <= n; ++k) {
    s += fmt::format("  - {{name: L{}, parent: {}, axis: z, angle: q{}}}\n", k,
                     k == 1 ? std::string("N") : fmt::format("L{}", k - 1), k);
  }
  s += "points:\n";
  for (int k = 1; k <= n; ++k) {
    s += fmt::format("  - {{name: P{}, from: {}, frame: L{}, position: [l, 0, 0]}}\n", k,
                     k == 1 ? std::string("O") : fmt::format("P{}", k - 1), k);
  }
  s += "particles:\n";
  for (int k = 1; k <= n; ++k) s += fmt::format("  - {{name: m{0}, point: P{0}, mass: m}}\n", k);
  s += "forces:\n";
  for (int k = 1; k <= n; ++k) {
    s += fmt::format("  - {{name: gravity{0}, point: P{0}, value: [m * g, 0, 0]}}\n", k);
  }
  if (slots > 0) {
    s += "slots:\n";
    for (int k = 1; k <= slots; ++k) {
      s += fmt::format("  - {{name: r{0}, unit: N·m, displacement: q{0}, stiffness: k}}\n", k);
    }
    s += "torques:\n";
    for (int k = 1; k <= slots; ++k) {
      s += fmt::format("  - {{name: joint{0}, frame: L{0}, value: [0, 0, -r{0}]}}\n", k);
      if (k > 1) s += fmt::format("  - {{name: joint{0} reaction, frame: L{1}, value: [0, 0, r{0}]}}\n", k, k - 1);
    }
  }
  return s;
}

}  // namespace hybridtest::test_support
