#pragma once
// TrackingSet: the tracking criteria J1–J3 (tracking_criteria.h) of every actuator of a paced
// run's physical substructures and of every slot they serve, fed once per tick with the run's
// exchanges (one per actuator, in the run's actuator order: runner/slot_map.h).
//
//   per actuator   its command against its measured position [m];
//   per slot       the slot's commanded displacement against its measured one, both seen
//                  through the pseudo-inverse of the setup's linearisation T0 (n × m):
//                  d = T0⁺ (a − p0) [m], exact for a linear setup with independent columns (for
//                  one actuator, (a − p0)/(sign·scale)).
//
// J2 and J3 are live; J1 is computed over all samples at the end (J1_ms) and, live, over the
// last `window` samples (UpdateLiveJ1: one actuator or slot per call, round robin, so that a
// tick never pays for all of them). Storage is allocated in Reserve; Add and UpdateLiveJ1
// allocate nothing.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <span>
#include <string>
#include <vector>

#include "hybridtest/runner/tracking_criteria.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

class TrackingSet {
 public:
  // One physical substructure.
  struct Block {
    std::string name;                // the spec's name
    int first_actuator = 0;          // its first actuator in the run's exchanges
    int num_actuators = 0;
    std::vector<std::string> slots;  // the model's names of the slots it serves
    Eigen::MatrixXd slot_of_actuator;  // T0⁺ (m × n) [m/m]
    Eigen::VectorXd p0;                // (n) [m]
  };

  // capacity: samples kept per channel; tick [s]; window: samples of the live J1.
  void Reserve(std::vector<Block> blocks, long capacity, double tick, long window);
  void Add(std::span<const substructures::Exchange> exchanges);
  // Recomputes the live J1 of the next channel (actuators, then slots).
  void UpdateLiveJ1();

  std::size_t num_actuators() const { return actuators_.size(); }
  const TrackingCriteria& actuator(std::size_t k) const { return actuators_[k]; }
  const TrackingCriteria& slot(std::size_t k) const { return slots_[k]; }
  // The live J1 of actuator k over the window [ms] (NaN until known).
  double live_J1_ms(std::size_t k) const { return live_[k]; }
  // {"actuators": [{substructure, actuator (1-based), J1_ms, J2, J3, samples}],
  //  "slots": [{slot, substructure, J1_ms, J2, J3, samples}]}.
  nlohmann::json ToJson() const;

 private:
  std::vector<Block> blocks_;
  std::vector<TrackingCriteria> actuators_, slots_;
  std::vector<double> live_;  // per actuator, then per slot [ms]
  long window_ = 0;
  std::size_t next_ = 0;
  Eigen::VectorXd a_c_, a_m_, d_c_, d_m_;  // work space (the largest block)
};

}  // namespace hybridtest::runner
