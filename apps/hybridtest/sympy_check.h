#pragma once
// The SymPy half of `hybridtest check-model`: runs check_model_sympy.py (shipped beside the
// binary as hybridtest_check_model_sympy.py), which reads the same model file on its own
// (PyYAML + SymPy's KanesMethod, no code shared with the engine) and evaluates M and g at the
// given states, with the rates ż of the extra states; the engine's M, g and ẋ are compared
// with them.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace hybridtest::app {

struct SympyState {
  double t = 0.0;      // [s]
  Eigen::VectorXd q;   // (n)
  Eigen::VectorXd u;   // (n)
  Eigen::VectorXd r;   // (num_slots)
  Eigen::VectorXd z;   // (num_extra_states)
};

struct SympyResult {
  std::vector<Eigen::MatrixXd> M;  // one (n × n) per state
  std::vector<Eigen::VectorXd> g;  // one (n) per state
  std::vector<Eigen::VectorXd> qdot;  // one (n) per state: q̇ = W(q) u
  std::vector<Eigen::VectorXd> zdot;  // one (nz) per state: the extra states' rates
};

// A wait status as words: "exit code 3", "killed by signal 9 (Killed)".
std::string DescribeStatus(int status);
// The last `lines` lines of `text` (a script's standard error), trimmed.
std::string LastLines(const std::string& text, int lines);

// The script's path beside the running binary, or nullopt (with the reason in `why`).
std::optional<std::string> FindSympyReader(std::string* why);
// The Python interpreter to use: $HYBRIDTEST_PYTHON, else /usr/bin/python3 (Debian's, with
// python3-sympy), else python3 on PATH. Empty with `why` set if none has sympy and yaml.
std::string FindPythonWithSympy(std::string* why);

// Runs the reader on `model_file` at `states`. Throws hybridtest::Error if the script fails.
// `timeout_s` > 0 stops the script after that many seconds (coreutils `timeout`).
SympyResult RunSympyReader(const std::string& python, const std::string& script,
                           const std::string& model_file, const std::vector<SympyState>& states,
                           double timeout_s = 0.0);

// The reduced equations of a model with constraints against SymPy: runs
// hybridtest_check_constraints_sympy.py (beside `reader_script`), which evaluates this binary's
// reduced M and forcing (`eom --assemble --json`) at `states` random consistent states and
// compares them with its own reduction of SymPy's M, g and constraint rows, with the dependent
// speeds the engine used. `report`: its lines (a summary, and each difference). Throws Error
// if it cannot run or fails otherwise, or after `timeout_s` (> 0).
struct ConstraintCheck {
  bool agree = false;
  std::string report;
};
ConstraintCheck RunConstraintCheck(const std::string& python, const std::string& reader_script,
                                   const std::string& model_file, int states, unsigned seed,
                                   double tolerance, double timeout_s = 0.0);

}  // namespace hybridtest::app
