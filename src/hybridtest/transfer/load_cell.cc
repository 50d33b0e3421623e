#include "hybridtest/transfer/load_cell.h"

#include <cmath>

namespace hybridtest::transfer {

LoadCell::LoadCell(double noise_std, double resolution, double offset, unsigned long seed)
    : noise_std_(noise_std), resolution_(resolution), offset_(offset), generator_(seed) {}

double LoadCell::Sample(double force) {
  double reading = force + offset_;
  if (noise_std_ > 0.0) reading += noise_std_ * normal_(generator_);
  if (resolution_ > 0.0) reading = resolution_ * std::round(reading / resolution_);
  return reading;
}

}  // namespace hybridtest::transfer
