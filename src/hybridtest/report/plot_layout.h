#pragma once
// What a run's channels mean for plotting, read from its channel names and its JSON sidecar:
// which channels are coordinates and speeds, which coordinates belong to physical
// substructures (to highlight them), whether the model is the paper's rotor (blades plus hub),
// and which channels record each physical substructure's actuator.
//
// Rules, in order:
//  - coordinates, speeds and restoring forces are the channels the sidecar's model.coordinates,
//    model.speeds and model.slots name (a model file's own names: x_t, psi, beta1, ...);
//    without them, the channels named q<k>, u<k> and r<k>;
//  - the model is the rotor when sidecar model.name contains "rotor" (any case); its blades
//    are q1..qN and its hub speed is u<N+1>, where N is the number of model.slots (or, without
//    slots, the number of coordinates minus one);
//  - a coordinate is physical when a substructure of kind "physical" has a slot whose
//    coordinate is known: from substructures[].coordinate, else model.slots[].coordinate (a
//    channel name such as "q1", or a 0-based index), else by the slot's number (r1 → q1);
//  - a physical substructure's channels come from substructures[].channels.{command, position,
//    force, lab_time}, else <slot>_command, <slot>_position, <slot>_force, <slot>_lab_time;
//    names that are not columns of the CSV are left empty.
// A run without a sidecar is a plain model: nothing physical, no rotor.
#include <Eigen/Core>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

struct PhysicalChannels {
  std::string slot;         // e.g. "r1"
  std::string coordinate;   // e.g. "q1"; empty when unknown
  std::string description;  // from the sidecar
  std::string command;      // channel names; empty when the CSV lacks them
  std::string position;
  std::string force;
  std::string lab_time;
  // Several actuators: the substructure's key in the config ("blade1") and this actuator's
  // index (0-based) among its actuators; one actuator: empty and −1 (`slot` is the key).
  std::string substructure;
  int actuator = -1;
};

struct RunLayout {
  std::string name;                         // run name: the CSV file name without extension
  std::string model_name;                   // sidecar model.name; empty without one
  bool is_rotor = false;
  std::vector<std::string> coordinates;     // coordinate channels, in the model's order
  std::vector<std::string> speeds;          // speed channels
  std::vector<std::string> restoring;       // restoring-force (slot) channels
  std::vector<std::string> blades;          // rotor only: q1..qN
  std::string hub_speed;                    // rotor only: u<N+1>; empty when absent
  std::set<std::string> physical_coordinates;
  std::vector<PhysicalChannels> physical;   // one per physical substructure
  std::map<std::string, std::string> slot_coordinates;  // every substructure's slot → q channel
};

RunLayout DescribeRun(const io::RunData& run);

// Run name: the CSV file name without its extension ("results/hybrid.csv" → "hybrid").
std::string RunName(const io::RunData& run);

// Column of channel name, or -1 when the run has no such channel.
int FindChannel(const io::RunData& run, const std::string& name);

// Unit of a channel as recorded ("m", "rad/s"), or "" when none was recorded.
std::string ChannelUnit(const io::RunData& run, const std::string& name);

// " [unit]", or " [unit not recorded]" when the run has no unit for the channel.
std::string UnitSuffix(const io::RunData& run, const std::string& name);

// A copy of one column. Throws IoError naming the run when the channel is missing.
Eigen::VectorXd ChannelValues(const io::RunData& run, const std::string& name);

}  // namespace hybridtest::report
