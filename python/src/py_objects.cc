// See py_objects.h.
#include "py_objects.h"

#include <fmt/core.h>

#include <cmath>

#include "bindings.h"
#include "hybridtest/common/error.h"
#include "hybridtest/common/units.h"
#include "hybridtest/runner/stop_request.h"

namespace hybridtest::python {
namespace {

std::string TypeName(const py::object& o) {
  return py::str(py::type::handle_of(o).attr("__name__"));
}

transfer::BenchUnits ReadUnits(const py::object& driver, const std::string& where) {
  transfer::BenchUnits units;
  if (!py::hasattr(driver, "units")) return units;
  const py::object given = driver.attr("units");
  std::string length, force;
  try {
    const auto pair = given.cast<std::pair<std::string, std::string>>();
    length = pair.first;
    force = pair.second;
  } catch (const py::cast_error&) {
    throw ConfigError(fmt::format("{}: units = {}: expected a pair of names such as (\"mm\", "
                                  "\"kN\") (length m | mm, force N | kN)", where,
                                  std::string(py::repr(given))));
  }
  if (length == "mm") {
    units.metres_per_length_unit = units::kMillimetre;
  } else if (length != "m") {
    throw ConfigError(fmt::format("{}: units length \"{}\": expected \"m\" or \"mm\"", where,
                                  length));
  }
  if (force == "kN") {
    units.newtons_per_force_unit = units::kKilonewton;
  } else if (force != "N") {
    throw ConfigError(fmt::format("{}: units force \"{}\": expected \"N\" or \"kN\"", where,
                                  force));
  }
  units.length_name = length;
  units.force_name = force;
  return units;
}

// The driver's attribute `name`, a positive length in its unit, or nullopt without one.
std::optional<double> ReadLength(const py::object& driver, const char* name,
                                 const std::string& where, const std::string& unit,
                                 const char* meaning) {
  if (!py::hasattr(driver, name)) return std::nullopt;
  const py::object given = driver.attr(name);
  double value = std::nan("");
  try {
    value = given.cast<double>();
  } catch (const py::cast_error&) {
  }
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw ConfigError(fmt::format("{}: {} = {}: expected a positive number, {} in {} (the "
                                  "driver's length unit)", where, name,
                                  std::string(py::repr(given)), meaning, unit));
  }
  return value;
}

const InCallback* g_callback = nullptr;                        // GIL held
std::optional<py::error_already_set>* g_kept = nullptr;        // GIL held; never freed

}  // namespace

const InCallback* CurrentCallback() { return g_callback; }

InCallback::InCallback(const char* method, const std::string& slot, const std::string& unit,
                       std::optional<double> command)
    : method_(method), slot_(slot), unit_(unit), command_(command), previous_(g_callback) {
  g_callback = this;
}

InCallback::~InCallback() { g_callback = previous_; }

std::string InCallback::Call() const {
  return command_ ? fmt::format("{}({} {})", method_, *command_, unit_)
                  : fmt::format("{}()", method_);
}

std::string InCallback::Describe() const {
  return fmt::format("the bench driver's {} of slot {}", Call(), slot_);
}

void KeepForCaller(py::error_already_set error) {
  if (g_kept == nullptr) g_kept = new std::optional<py::error_already_set>();
  if (!g_kept->has_value()) g_kept->emplace(std::move(error));
}

std::optional<py::error_already_set> TakeKeptForCaller() {
  if (g_kept == nullptr || !g_kept->has_value()) return std::nullopt;
  std::optional<py::error_already_set> out = std::move(*g_kept);
  g_kept->reset();
  return out;
}

std::string InterruptOrDescribe(py::error_already_set& e, const std::string& where,
                                const std::string& consequence) {
  const std::string described = DescribePythonError(e);
  if (e.matches(PyExc_Exception)) return described;
  KeepForCaller(std::move(e));
  throw runner::Interrupted(fmt::format("{} inside {}: {}", described, where, consequence));
}

SharedObject::SharedObject(py::object object) : object_(std::move(object)) {}

SharedObject::~SharedObject() {
  py::gil_scoped_acquire gil;
  object_ = py::object();
}

PyTransfer::PyTransfer(SharedPy driver, std::string slot, transfer::SafetyLimits limits)
    : driver_(std::move(driver)), slot_(std::move(slot)), timeout_(limits.timeout) {
  py::gil_scoped_acquire gil;
  const py::object& d = driver_->get();
  const std::string where = fmt::format("transfers[\"{}\"] ({})", slot_, TypeName(d));
  for (const char* method : {"activate", "execute", "hold", "deactivate"}) {
    if (!py::hasattr(d, method)) {
      throw ConfigError(fmt::format("{}: a Python transfer system needs the methods activate(), "
                                    "execute(command), hold() and deactivate(); {}() is "
                                    "missing", where, method));
    }
  }
  units_ = ReadUnits(d, where);
  if (py::hasattr(d, "p0")) {
    const py::object given = d.attr("p0");
    double p0 = 0.0;
    try {
      p0 = given.cast<double>();
    } catch (const py::cast_error&) {
      p0 = std::nan("");
    }
    if (!std::isfinite(p0)) {
      throw ConfigError(fmt::format("{}: p0 = {}: expected a finite number, the actuator's "
                                    "zero-force position in {}", where,
                                    std::string(py::repr(given)), units_.length_name));
    }
    p0_ = p0 * units_.metres_per_length_unit;
  }
  // The settled-reply check, in the driver's length unit.
  const double metres = units_.metres_per_length_unit;
  const double settle = ReadLength(d, "settle_tolerance", where, units_.length_name,
                                   "the bench's settling (in-position) window")
                            .value_or(transfer::InBenchUnit(transfer::kDefaultSettleTolerance,
                                                            metres));
  const std::optional<double> following =
      ReadLength(d, "following_error", where, units_.length_name,
                 "the largest |command − position| of a settled reply");
  if (following && *following * metres > limits.stroke_max - limits.stroke_min) {
    throw ConfigError(fmt::format("{}: following_error = {} {} is longer than the whole stroke "
                                  "({} m to {} m), so it could never stop anything: give it in "
                                  "{} (the driver's length unit)", where, *following,
                                  units_.length_name, limits.stroke_min, limits.stroke_max,
                                  units_.length_name));
  }
  transfer::SettledReadingCheck::Limits reply;
  reply.settle_tolerance = settle;
  reply.following_error = following.value_or(transfer::DefaultFollowingError(
      settle, transfer::InBenchUnit(limits.max_increment, metres)));
  settled_ = transfer::SettledReadingCheck({reply});
  // How a failed check names this driver (built once: Execute stays cheap).
  reply_source_.unit = units_.length_name;
  reply_source_.metres_per_unit = metres;
  reply_source_.answered = [this](std::size_t) {
    return fmt::format("The Python transfer system of slot {} answered execute({} {})", slot_,
                       command_now_, units_.length_name);
  };
  reply_source_.detail = [this](std::size_t) {
    return fmt::format(" (force {} {})", force_now_, units_.force_name);
  };
  reply_source_.after = "the run holds (hold() is called)";
  reply_source_.following_key = "the driver's attribute following_error";
  reply_source_.settle_key = "the driver's attribute settle_tolerance";
  description_ = fmt::format("Python transfer system {} ({}, {})", TypeName(d),
                             units_.length_name, units_.force_name);
}

void PyTransfer::Call(const char* method, const std::string& what) {
  py::gil_scoped_acquire gil;
  InCallback inside(method, slot_, units_.length_name);
  try {
    driver_->get().attr(method)();
  } catch (py::error_already_set& e) {
    const std::string described = InterruptOrDescribe(
        e, fmt::format("the Python transfer system's {} of slot {}", what, slot_),
        "the bench holds; every committed step is kept");
    throw TransferError(fmt::format("the Python transfer system's {} raised {}", what, described));
  }
}

transfer::BenchAnnouncement PyTransfer::Announce() const {
  transfer::BenchAnnouncement a;
  a.p0 = p0_;
  a.source = fmt::format("the Python transfer system of {}", slot_);
  return a;
}

void PyTransfer::Activate() {
  Call("activate", "activate()");
  settled_.Reset();  // the actuator may have been moved while it was not ours
  activated_ = std::chrono::steady_clock::now();
}

transfer::Measurement PyTransfer::Execute(double command) {
  py::gil_scoped_acquire gil;
  transfer::Measurement m;
  std::string problem;
  bool lab_time_given = false;
  InCallback inside("execute", slot_, units_.length_name, command);
  const auto started = std::chrono::steady_clock::now();
  try {
    const py::object reply = driver_->get().attr("execute")(command);
    if (!py::isinstance<py::sequence>(reply) || py::isinstance<py::str>(reply)) {
      throw py::cast_error("got " + std::string(py::repr(reply)));
    }
    const py::tuple values = py::tuple(reply);
    if (values.size() != 2 && values.size() != 3) {
      problem = fmt::format("returned {} values; expected (position, force[, lab_time])",
                            values.size());
    } else {
      m.position = values[0].cast<double>();
      m.force = values[1].cast<double>();
      if (values.size() == 3) {
        m.lab_time = values[2].cast<double>();
        lab_time_given = true;
      }
    }
  } catch (py::error_already_set& e) {
    // Ctrl-C while the driver runs is not a transfer failure: the run holds after this step.
    problem = "raised " + InterruptOrDescribe(
        e, fmt::format("the Python transfer system's {} of slot {}", inside.Call(), slot_),
        "the bench holds; every committed step is kept");
  } catch (const py::cast_error& e) {
    problem = fmt::format("returned something that is not (position, force[, lab_time]) "
                          "numbers ({})", e.what());
  }
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!problem.empty()) {
    throw TransferError(fmt::format("the Python transfer system's {} {}", inside.Call(),
                                    problem));
  }
  // A reply that came after the slot's timeout is not trusted: the bench was not in control
  // of the time (a call that never returns is stopped with Ctrl-C).
  if (took > timeout_) {
    throw TransferError(fmt::format(
        "the Python transfer system's {} took {:.3f} s, longer than the slot's safety.timeout "
        "{} s (substructures.{}.safety.timeout): its reply is not used and the run holds. Find "
        "out why the bench answers that slowly; if a move really takes that long, raise the "
        "timeout", inside.Call(), took, timeout_, slot_));
  }
  if (!std::isfinite(m.position) || !std::isfinite(m.force) || !std::isfinite(m.lab_time)) {
    throw TransferError(fmt::format("the Python transfer system's execute({} {}) returned a "
                                    "value that is not finite (position {}, force {})", command,
                                    units_.length_name, m.position, m.force));
  }
  // The same check as a Modbus controller's ack: where it was sent, and not a stale reply.
  command_now_ = command;
  force_now_ = m.force;
  settled_.Check({&command, 1}, {&m.position, 1}, reply_source_);
  if (!lab_time_given) {
    m.lab_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - activated_)
                     .count();
  }
  return m;
}

void PyTransfer::Hold() noexcept {
  try {
    py::gil_scoped_acquire gil;
    InCallback inside("hold", slot_, units_.length_name);
    try {
      driver_->get().attr("hold")();
    } catch (py::error_already_set& e) {
      // Hold never throws; the error is reported as an unraisable exception.
      e.discard_as_unraisable(fmt::format("hold() of the Python transfer system of slot {}",
                                          slot_).c_str());
    }
  } catch (...) {
  }
}

void PyTransfer::Deactivate() { Call("deactivate", "deactivate()"); }

PyLaw::PyLaw(SharedPy law, std::string slot) : law_(std::move(law)), slot_(std::move(slot)) {
  py::gil_scoped_acquire gil;
  const py::object& f = law_->get();
  if (!PyCallable_Check(f.ptr())) {
    throw ConfigError(fmt::format("laws[\"{}\"]: expected a callable r = law(d) [m] -> [N], "
                                  "got {}", slot_, std::string(py::repr(f))));
  }
  description_ = "Python law " + (py::hasattr(f, "__qualname__")
                                      ? std::string(py::str(f.attr("__qualname__")))
                                      : TypeName(f));
  if (py::hasattr(f, "initial_stiffness")) {
    k0_ = f.attr("initial_stiffness").cast<double>();
  } else {
    const double h = 1e-6;  // [m]
    k0_ = (Evaluate(h) - Evaluate(-h)) / (2.0 * h);
  }
}

double PyLaw::Evaluate(double displacement) const {
  try {
    return law_->get()(displacement).cast<double>();
  } catch (py::error_already_set& e) {
    const std::string described = InterruptOrDescribe(
        e, fmt::format("the Python law of slot {} at d = {} m", slot_, displacement),
        "the run holds; every committed step is kept");
    throw Error(fmt::format("slot {}: the Python law raised {} at d = {} m", slot_, described,
                            displacement));
  } catch (const py::cast_error&) {
    throw Error(fmt::format("slot {}: the Python law returned something that is not a number "
                            "at d = {} m: return the force in N", slot_, displacement));
  }
}

double PyLaw::Trial(double displacement) {
  py::gil_scoped_acquire gil;
  return Evaluate(displacement);
}

void PyLaw::Commit() {
  py::gil_scoped_acquire gil;
  const py::object& f = law_->get();
  if (!py::hasattr(f, "commit")) return;
  try {
    f.attr("commit")();
  } catch (py::error_already_set& e) {
    const std::string described = InterruptOrDescribe(
        e, fmt::format("the Python law's commit() of slot {}", slot_),
        "the run holds; every committed step is kept");
    throw Error(fmt::format("slot {}: the Python law's commit() raised {}", slot_, described));
  }
}

}  // namespace hybridtest::python
