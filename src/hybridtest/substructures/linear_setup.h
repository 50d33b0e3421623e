#pragma once
// LinearSetup: the geometry of a test setup with n actuators on a specimen that serves m slots
// (setup_transform.h's keys are its one-actuator form, OneActuatorSetup in actuator_setup.h):
//
//   commands      a = p0 + T d                       [m]   (T: n × m, full column rank)
//   forces        f_k = measured_k − load_cell_zero_k  [N]
//   slot forces   r = Rᵀ f                            [N]   (R = T unless given)
//
// so that dr/dd = Rᵀ K_a T for a specimen of stiffness K_a in actuator coordinates (Tᵀ K_a T:
// virtual work). R differs from T only where the load cells are read through another factor
// than the actuators are commanded (the one-actuator form's force_sign · force_scale).
#include <Eigen/Core>

namespace hybridtest::substructures {

struct LinearSetup {
  Eigen::VectorXd p0;              // (n) actuator positions at zero specimen force [m]
  Eigen::MatrixXd transform;       // T (n × m) [m/m]: actuator displacement per slot displacement
  Eigen::VectorXd load_cell_zero;  // (n) readings at zero load, subtracted [N]
  Eigen::MatrixXd force_transform;  // R (n × m) [N/N], or empty: R = T

  int num_actuators() const { return static_cast<int>(transform.rows()); }
  int num_slots() const { return static_cast<int>(transform.cols()); }
  // Throws ConfigError if the sizes do not fit, a value is not finite, or T (or R) has not
  // full column rank (two slots the actuators cannot tell apart).
  void Validate() const;
};

}  // namespace hybridtest::substructures
