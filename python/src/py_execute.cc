// PyTransfer::Execute: the driver's execute() on a thread of its own, bounded by the slot's
// safety.timeout (py_objects.h, bounded_call.h), and its reply read and checked.
#include <fmt/core.h>

#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/stop_request.h"
#include "py_objects.h"

namespace hybridtest::python {

bool PyTransfer::ReadReply(const py::object& reply, std::size_t n,
                           std::span<transfer::Measurement> out, std::string& problem) {
  if (!py::isinstance<py::sequence>(reply) || py::isinstance<py::str>(reply)) {
    throw py::cast_error("got " + std::string(py::repr(reply)));
  }
  const py::tuple values = py::tuple(reply);
  const char* shape = n == 1 ? "(position, force[, lab_time])"
                              : "(positions, forces[, lab_time]) with n values in each list";
  if (values.size() != 2 && values.size() != 3) {
    problem = fmt::format("returned {} values; expected {}", values.size(), shape);
    return false;
  }
  if (n == 1) {
    out[0].position = values[0].cast<double>();
    out[0].force = values[1].cast<double>();
  } else {
    const char* names[] = {"positions", "forces"};
    for (std::size_t i = 0; i < 2; ++i) {
      const py::handle list = values[i];
      if (!py::isinstance<py::sequence>(list) || py::isinstance<py::str>(list)) {
        problem = fmt::format("returned {} {} for its {}; expected a list or array of {} numbers, "
                              "one per actuator", names[i], std::string(py::repr(list)),
                              names[i], n);
        return false;
      }
      const auto items = py::reinterpret_borrow<py::sequence>(list);
      if (items.size() != n) {
        problem = fmt::format("returned {} {}; expected {}, one per actuator", items.size(),
                              names[i], n);
        return false;
      }
      for (std::size_t k = 0; k < n; ++k) {
        const double v = items[k].cast<double>();
        (i == 0 ? out[k].position : out[k].force) = v;
      }
    }
  }
  if (values.size() == 3) {
    const double lab_time = values[2].cast<double>();
    for (auto& m : out) m.lab_time = lab_time;
  }
  return values.size() == 3;
}

namespace {
// One execute() on the worker thread: what it needs and what it gives, kept alive by the
// worker even when the call is abandoned (bounded_call.h).
struct ExecuteCall {
  SharedPy driver;
  std::string slot;  // copies: an abandoned call may outlive its PyTransfer
  std::string unit;
  std::vector<double> commands;  // (bench units)
  std::vector<transfer::Measurement> out;
  std::string problem;
  bool lab_time_given = false;
  std::optional<py::error_already_set> error;
};
}  // namespace

void PyTransfer::Execute(std::span<const double> commands,
                         std::span<transfer::Measurement> out) {
  if (commands.size() != n_ || out.size() != n_) {
    throw TransferError(fmt::format("{}: {} commands for {} actuators", description_,
                                    commands.size(), n_));
  }
  for (auto& m : out) m = {};
  auto call = std::make_shared<ExecuteCall>();
  call->driver = driver_;
  call->slot = slot_;
  call->unit = units_.length_name;
  call->commands.assign(commands.begin(), commands.end());
  call->out.resize(n_);
  const std::size_t n = n_;
  const auto started = std::chrono::steady_clock::now();
  // The call, on the worker: the GIL, the driver's execute(), its reply read.
  auto job = [call, n] {
    py::gil_scoped_acquire gil;
    // The worker's thread state is kept between calls (not made and freed for each).
    thread_local const bool kept = (gil.inc_ref(), true);
    (void)kept;
    ExecuteCall& c = *call;
    InCallback inside("execute", c.slot, c.unit, c.commands);
    try {
      // One actuator: a float; several: a fresh array the driver may keep or change.
      const py::object argument =
          n == 1 ? py::object(py::float_(c.commands[0]))
                 : py::object(py::array_t<double>(static_cast<py::ssize_t>(n), c.commands.data()));
      const py::object reply = c.driver->get().attr("execute")(argument);
      c.lab_time_given = ReadReply(reply, n, c.out, c.problem);
    } catch (py::error_already_set& e) {
      c.error.emplace(std::move(e));
    } catch (const py::cast_error& e) {
      c.problem = fmt::format("returned something that is not {} numbers ({})",
                              n == 1 ? "(position, force[, lab_time])"
                                     : "(positions, forces[, lab_time])",
                              e.what());
    }
  };
  std::optional<py::error_already_set> signal;
  const BoundedCall::Outcome outcome = execute_call_.Run(std::move(job), timeout_, &signal);
  const std::string where =
      fmt::format("the Python transfer system's {} of slot {}", ExecuteText(commands), slot_);
  const char* consequence = "the bench holds; every committed step is kept";
  if (outcome == BoundedCall::Outcome::kInterrupted) {
    // Ctrl-C while the driver runs is not a transfer failure: the run holds after this step.
    py::gil_scoped_acquire gil;
    InterruptOrDescribe(*signal, where, consequence);
    throw runner::Interrupted(fmt::format("interrupted inside {}: {}", where, consequence));
  }
  if (outcome == BoundedCall::Outcome::kTimedOut) {
    throw TransferError(fmt::format(
        "the Python transfer system's {} did not return within the slot's safety.timeout {} s "
        "(substructures.{}.safety.timeout): the run stops and the bench is told to hold "
        "(hold() is called; a Python call cannot be stopped: it is left running and its reply "
        "is dropped). Find out why the driver does not answer; if a move really takes that "
        "long, raise the timeout", ExecuteText(commands), timeout_, slot_));
  }
  if (outcome == BoundedCall::Outcome::kBusy) {
    throw TransferError(fmt::format(
        "the Python transfer system's {} cannot start: an earlier execute() of slot {} did not "
        "return within safety.timeout and is still running (a Python call cannot be stopped); "
        "the bench holds. Restart the process once the driver is fixed",
        ExecuteText(commands), slot_));
  }
  std::string problem = std::move(call->problem);
  const bool lab_time_given = call->lab_time_given;
  std::copy(call->out.begin(), call->out.end(), out.begin());
  if (call->error) {
    py::gil_scoped_acquire gil;
    problem = "raised " + InterruptOrDescribe(*call->error, where, consequence);
    KeepCause(*call->error);
    call->error.reset();
  }
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!problem.empty()) {
    throw TransferError(fmt::format("the Python transfer system's {} {}", ExecuteText(commands),
                                    problem));
  }
  // A reply that came after the slot's timeout is not trusted: the bench was not in control
  // of the time (a call that never returns is stopped with Ctrl-C).
  if (took > timeout_) {
    throw TransferError(fmt::format(
        "the Python transfer system's {} took {:.3f} s, longer than the slot's safety.timeout "
        "{} s (substructures.{}.safety.timeout): its reply is not used and the run holds. Find "
        "out why the bench answers that slowly; if a move really takes that long, raise the "
        "timeout", ExecuteText(commands), took, timeout_, slot_));
  }
  for (std::size_t k = 0; k < n_; ++k) {
    const transfer::Measurement& m = out[k];
    if (!std::isfinite(m.position) || !std::isfinite(m.force) || !std::isfinite(m.lab_time)) {
      throw TransferError(fmt::format("the Python transfer system's {} returned a value that is "
                                      "not finite{} (position {} {}, force {} {})", ExecuteText(commands),
                                      n_ == 1 ? "" : fmt::format(" for actuator {}", k + 1),
                                      m.position, units_.length_name, m.force,
                                      units_.force_name));
    }
    positions_[k] = m.position;
    forces_[k] = m.force;
  }
  // The same check as a Modbus controller's ack: where it was sent, and not a stale reply.
  commands_now_ = commands;
  settled_.Check(commands, positions_, reply_source_);
  if (!lab_time_given) {
    const double lab_time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - activated_).count();
    for (auto& m : out) m.lab_time = lab_time;
  }
}

}  // namespace hybridtest::python
