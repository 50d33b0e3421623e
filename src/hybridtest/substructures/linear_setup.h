#pragma once
// LinearSetup: the geometry of a test setup with n actuators on a specimen that serves m slots
// (setup_transform.h is its one-actuator form, with its own keys and arithmetic):
//
//   commands      a = p0 + T d                       [m]   (T: n × m, full column rank)
//   forces        f_k = measured_k − load_cell_zero_k  [N]
//   slot forces   r = Tᵀ f                            [N]
//
// so that dr/dd = Tᵀ K_a T for a specimen of stiffness K_a in actuator coordinates.
#include <Eigen/Core>

namespace hybridtest::substructures {

struct LinearSetup {
  Eigen::VectorXd p0;              // (n) actuator positions at zero specimen force [m]
  Eigen::MatrixXd transform;       // T (n × m) [m/m]: actuator displacement per slot displacement
  Eigen::VectorXd load_cell_zero;  // (n) readings at zero load, subtracted [N]

  int num_actuators() const { return static_cast<int>(transform.rows()); }
  int num_slots() const { return static_cast<int>(transform.cols()); }
  // Throws ConfigError if the sizes do not fit, a value is not finite, or T has not full
  // column rank (two slots the actuators cannot tell apart).
  void Validate() const;
};

}  // namespace hybridtest::substructures
