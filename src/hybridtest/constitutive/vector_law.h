#pragma once
// VectorRestoringForceLaw: a coupled static restoring-force law F = R(u) of a specimen loaded
// along n axes at once (the specimen of a bench with n actuators: u_k = p_k − p0_k is actuator
// k's displacement from its zero-force position [m], F_k the force on actuator k [N]). The
// n-axis counterpart of RestoringForceLaw (restoring_force_law.h), with the same two phases:
//   Trial(u, F)  the forces at u, reached from the COMMITTED state along the straight path;
//                any number of calls; never changes the committed state.
//   Commit()     makes the state of the last Trial permanent.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <memory>
#include <span>
#include <string>

namespace hybridtest::constitutive {

class VectorRestoringForceLaw {
 public:
  virtual ~VectorRestoringForceLaw() = default;

  // Axes n (actuators of the specimen).
  virtual int num_axes() const = 0;
  // u (n) [m] → F (n) [N], from the committed state. Does not change the committed state.
  virtual void Trial(std::span<const double> u, std::span<double> force) = 0;
  // Makes the last trial permanent. Without a preceding Trial, it does nothing.
  virtual void Commit() = 0;
  // Tangent stiffness dF/du at the undeformed, virgin state (n × n). Unit: [N/m].
  virtual Eigen::MatrixXd initial_stiffness() const = 0;
  // An independent copy with the same parameters and the same committed state.
  virtual std::unique_ptr<VectorRestoringForceLaw> Clone() const = 0;
  // One line for logs.
  virtual std::string Describe() const = 0;
  // The committed state in SI ({} for an elastic law); RestoreState(SaveState()) continues
  // bit-identically. RestoreState throws hybridtest::Error on a state of another law.
  virtual nlohmann::json SaveState() const { return nlohmann::json::object(); }
  virtual void RestoreState(const nlohmann::json& /*state*/) {}
};

// F = K u with a constant n × n stiffness K [N/m] (any finite square matrix).
class LinearCoupledLaw final : public VectorRestoringForceLaw {
 public:
  // Throws ConfigError unless K is square, non-empty and finite.
  explicit LinearCoupledLaw(Eigen::MatrixXd stiffness);
  int num_axes() const override { return static_cast<int>(k_.rows()); }
  void Trial(std::span<const double> u, std::span<double> force) override;
  void Commit() override {}
  Eigen::MatrixXd initial_stiffness() const override { return k_; }
  std::unique_ptr<VectorRestoringForceLaw> Clone() const override;
  std::string Describe() const override;
  const Eigen::MatrixXd& stiffness() const { return k_; }

 private:
  Eigen::MatrixXd k_;
};

}  // namespace hybridtest::constitutive
