#pragma once
// LoadCell: the emulated force transducer. One raw sample is
//   quantise(force + offset + N(0, noise_std²)),  quantise(f) = resolution · round(f / resolution)
// (no quantisation when resolution = 0). The generator is seeded, so a run is reproducible.
// All SI: [N].
#include <random>
#include <string>

namespace hybridtest::transfer {

class LoadCell {
 public:
  // noise_std, resolution, offset [N] (non-negative noise_std and resolution); seed of the RNG.
  LoadCell(double noise_std, double resolution, double offset, unsigned long seed);

  // One raw reading of the true force `force` [N]. Unit: [N].
  double Sample(double force);
  // The generator's and the distribution's state as text (std's stream format), for a
  // checkpoint; RestoreState(SaveState()) draws the same numbers next. Throws hybridtest::Error.
  std::string SaveState() const;
  void RestoreState(const std::string& state);

 private:
  double noise_std_;
  double resolution_;
  double offset_;
  std::mt19937_64 generator_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace hybridtest::transfer
