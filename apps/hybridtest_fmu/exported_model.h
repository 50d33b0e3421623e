#pragma once
// ExportedModel: the inside of an FMU written by `hybridtest export-fmu`, free of FMI types
// (exported_fmu.cc wraps it for the shared entry points fmi/fmu_entry.c). It reads resources/hybridtest/ (the
// reduced config and export.json, export_layout.h), and at the end of initialization builds
// a Session (runner/session.h) of that config, in memory (no file), with the model parameters
// the master set, every exported slot served by a FedSlots substructure below, and every
// other slot by the model's default numerical substructure.
//
// The exported slots are what the co-simulation master serves: it reads their displacements
// d_c at the communication point t_c, computes their restoring forces f and sets them as the
// inputs before DoStep(t_c, h). Inside the step the scheme tries the slots at other
// displacements d (its stages); the master is not there to answer, so a trial returns the
// force linearized about the communication point with the slot's K0 (from the config):
//
//   r(d) = f + K0 (d − d_c)
//
// exact for a linear specimen of stiffness K0 (so the FMU stepped at dt with r = K0 d fed back
// reproduces `simulate`), first order otherwise, as operator splitting is. DoStep advances the
// configured scheme by h = a whole number of its steps dt.
//
// The FMU state (get/set/serialize) is the Session's RunState (what `resume` continues from)
// with every variable's value (the parameters in effect among them) and the feed; setting it,
// in this instance or a fresh one, puts those parameters in effect and builds a fresh Session
// continued from that state.
// Errors throw hybridtest::Error, which the C functions turn into fmi2Error with a log line.
#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "export_layout.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::fmu_export {

// What the master gave for the step in progress, shared by the FedSlots of a session: per
// exported slot (layout order), the force f [N] and the displacement d_c [m] it is about.
struct Feed {
  Eigen::VectorXd force;
  Eigen::VectorXd about;
};

class ExportedModel {
 public:
  // `resources`: the FMU's resources folder. Throws ConfigError.
  explicit ExportedModel(const std::string& resources);
  ~ExportedModel();

  const Layout& layout() const { return layout_; }
  // Before Initialize(): the time the run starts at (must be 0: the config's initial state
  // is at t = 0) and the stop time (the session's end; none: as long as kMaxSteps allows).
  void SetupExperiment(double start, std::optional<double> stop);
  // Parameters before Initialize(); inputs at any time. Throws Error for a wrong reference.
  void Set(unsigned vr, double value);
  double Get(unsigned vr) const;
  // Compiles the config with the parameters set, builds the session and initializes it.
  void Initialize();
  // One communication step from t [s] (the FMU's time) of h [s] (a multiple of dt).
  void DoStep(double t, double h);
  double time() const { return t_; }

  // The FMU state as bytes (JSON text), and back (after Initialize()).
  std::string SaveState() const;
  void RestoreState(const std::string& bytes);

 private:
  io::RunSpec Compile() const;
  std::unique_ptr<runner::Session> NewSession() const;
  void ReadOutputs();
  void Check(const runner::StepResult& result, const std::string& what) const;

  std::string config_path_;  // resources/hybridtest/<config>
  std::string config_text_;
  Layout layout_;
  std::vector<double> values_;       // per value reference
  std::vector<bool> parameter_set_;  // per parameter: the master set it
  std::vector<int> slot_of_;         // per exported slot: its model slot index
  std::optional<io::RunSpec> spec_;
  std::shared_ptr<Feed> feed_;
  std::unique_ptr<runner::Session> session_;
  double t_ = 0.0;
  std::optional<double> stop_;
  bool initialized_ = false;
};

}  // namespace hybridtest::fmu_export
