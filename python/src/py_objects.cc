// See py_objects.h.
#include "py_objects.h"

#include <fmt/core.h>

#include <pybind11/numpy.h>

#include <algorithm>
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

// The driver's attribute `name` in its length unit, one value per actuator: a number (for
// every actuator) or a sequence of n numbers; empty without the attribute. `positive`: each
// must be > 0, else finite.
std::vector<double> ReadLengths(const py::object& driver, const char* name,
                                const std::string& where, const std::string& unit, std::size_t n,
                                bool positive, const char* meaning) {
  if (!py::hasattr(driver, name)) return {};
  const py::object given = driver.attr(name);
  std::vector<double> values;
  try {
    if (py::isinstance<py::sequence>(given) && !py::isinstance<py::str>(given)) {
      for (const py::handle item : py::reinterpret_borrow<py::sequence>(given)) {
        values.push_back(item.cast<double>());
      }
    } else {
      values.assign(n, given.cast<double>());
    }
  } catch (const py::cast_error&) {
    values.clear();
  }
  const bool fit = values.size() == n &&
                   std::all_of(values.begin(), values.end(), [positive](double v) {
                     return std::isfinite(v) && (!positive || v > 0.0);
                   });
  if (!fit) {
    const std::string each = n == 1 ? "" : fmt::format(" (or a list of {}, one per actuator)", n);
    throw ConfigError(fmt::format("{}: {} = {}: expected a {} number{}, {} in {} (the driver's "
                                  "length unit)", where, name, std::string(py::repr(given)),
                                  positive ? "positive" : "finite", each, meaning, unit));
  }
  return values;
}

// "0.0213", or "[0.02, 0.0312]" for several.
std::string FormatLengths(std::span<const double> values) {
  if (values.size() == 1) return fmt::format("{:.6g}", values[0]);
  std::string out = "[";
  for (std::size_t k = 0; k < values.size(); ++k) {
    out += fmt::format("{}{:.6g}", k > 0 ? ", " : "", values[k]);
  }
  return out + "]";
}

// Per thread: a driver's execute() runs on a thread of its own (bounded_call.h), and an
// abandoned one may still be inside while the caller's thread runs hold().
thread_local const InCallback* g_callback = nullptr;           // GIL held
std::optional<py::error_already_set>* g_kept = nullptr;        // GIL held; never freed

}  // namespace

const InCallback* CurrentCallback() { return g_callback; }

InCallback::InCallback(const char* method, const std::string& slot, const std::string& unit,
                       std::span<const double> commands)
    : method_(method), slot_(slot), unit_(unit), commands_(commands), previous_(g_callback) {
  g_callback = this;
}

InCallback::~InCallback() { g_callback = previous_; }

std::string InCallback::Call() const {
  return commands_.empty() ? fmt::format("{}()", method_)
                           : fmt::format("{}({} {})", method_, FormatLengths(commands_), unit_);
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

PyTransfer::PyTransfer(SharedPy driver, std::string slot,
                       std::vector<transfer::SafetyLimits> limits, DriverCauseSlot cause)
    : driver_(std::move(driver)), slot_(std::move(slot)), n_(limits.size()),
      cause_(std::move(cause)) {
  if (limits.empty()) throw Error("PyTransfer: no actuator limits given");
  timeout_ = limits[0].timeout;
  for (const auto& l : limits) timeout_ = std::max(timeout_, l.timeout);  // the slowest
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
  // A driver that says how many actuators it moves must move the specimen's.
  if (py::hasattr(d, "actuators")) {
    const py::object given = d.attr("actuators");
    long declared = -1;
    try {
      declared = given.cast<long>();
    } catch (const py::cast_error&) {
    }
    if (declared != static_cast<long>(n_)) {
      throw ConfigError(fmt::format(
          "{}: actuators = {}, but substructure {} is set up on {} actuator{} "
          "(substructures.{}.setup): give the specimen a driver of {} (execute then receives "
          "{}), or set up the substructure for the driver's actuators",
          where, std::string(py::repr(given)), slot_, n_, n_ == 1 ? "" : "s", slot_, n_,
          n_ == 1 ? "one command, a float" : fmt::format("an array of {} commands", n_)));
    }
  }
  units_ = ReadUnits(d, where);
  const double metres = units_.metres_per_length_unit;
  const std::string& unit = units_.length_name;
  p0_ = ReadLengths(d, "p0", where, unit, n_, false, "the actuator's zero-force position");
  for (double& p : p0_) p *= metres;
  // The settled-reply check, in the driver's length unit.
  const std::vector<double> settle = ReadLengths(d, "settle_tolerance", where, unit, n_, true,
                                                 "the bench's settling (in-position) window");
  const std::vector<double> following =
      ReadLengths(d, "following_error", where, unit, n_, true,
                  "the largest |command − position| of a settled reply");
  std::vector<transfer::SettledReadingCheck::Limits> replies(n_);
  for (std::size_t k = 0; k < n_; ++k) {
    const transfer::SafetyLimits& l = limits[k];
    const std::string actuator = n_ == 1 ? "" : fmt::format(" (actuator {})", k + 1);
    if (!following.empty() && following[k] * metres > l.stroke_max - l.stroke_min) {
      throw ConfigError(fmt::format("{}: following_error{} = {} {} is longer than the whole "
                                    "stroke ({} m to {} m), so it could never stop anything: "
                                    "give it in {} (the driver's length unit)", where, actuator,
                                    following[k], unit, l.stroke_min, l.stroke_max, unit));
    }
    replies[k].settle_tolerance =
        settle.empty() ? transfer::InBenchUnit(transfer::kDefaultSettleTolerance, metres)
                       : settle[k];
    replies[k].following_error =
        following.empty() ? transfer::DefaultFollowingError(
                                replies[k].settle_tolerance,
                                transfer::InBenchUnit(l.max_increment, metres))
                          : following[k];
  }
  settled_ = transfer::SettledReadingCheck(std::move(replies));
  positions_.resize(n_);
  forces_.resize(n_);
  // How a failed check names this driver (built once: Execute stays cheap).
  reply_source_.unit = unit;
  reply_source_.metres_per_unit = metres;
  reply_source_.answered = [this](std::size_t k) {
    return fmt::format("The Python transfer system of slot {}{} answered execute({} {})", slot_,
                       n_ == 1 ? "" : fmt::format(" (actuator {})", k + 1),
                       FormatLengths(commands_now_), units_.length_name);
  };
  reply_source_.detail = [this](std::size_t k) {
    return fmt::format(" (force {:.6g} {})", forces_[k], units_.force_name);
  };
  reply_source_.after = "the run holds (hold() is called)";
  reply_source_.following_key = "the driver's attribute following_error";
  reply_source_.settle_key = "the driver's attribute settle_tolerance";
  description_ = fmt::format("Python transfer system {} ({}, {}{})", TypeName(d), unit,
                             units_.force_name,
                             n_ == 1 ? "" : fmt::format(", {} actuators", n_));
}

void PyTransfer::KeepCause(const py::error_already_set& e) {
  if (!cause_) return;
  const py::object value = e.value();
  // Where in the driver it was raised (the value alone may not carry it yet).
  PyObject* traceback = PyException_GetTraceback(value.ptr());  // a new reference, or null
  if (traceback == nullptr && e.trace()) PyException_SetTraceback(value.ptr(), e.trace().ptr());
  Py_XDECREF(traceback);
  cause_->exception = std::make_shared<SharedObject>(value);
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
    KeepCause(e);
    throw TransferError(fmt::format("the Python transfer system's {} raised {}", what, described));
  }
}

transfer::BenchAnnouncement PyTransfer::Announce() const {
  transfer::BenchAnnouncement a;
  for (double p0 : p0_) a.actuators.push_back({p0, std::nullopt});
  a.source = fmt::format("the Python transfer system of {}", slot_);
  return a;
}

std::optional<std::vector<transfer::Measurement>> PyTransfer::ReadAll() {
  py::gil_scoped_acquire gil;
  try {
    const py::object& driver = driver_->get();
    if (!py::hasattr(driver, "read")) return std::nullopt;
    std::vector<transfer::Measurement> out(n_);
    std::string problem;
    ReadReply(driver.attr("read")(), n_, out, problem);
    if (!problem.empty()) return std::nullopt;
    return out;
  } catch (const std::exception&) {
    return std::nullopt;  // py::error_already_set included: the run records "not read"
  }
}

void PyTransfer::Activate() {
  Call("activate", "activate()");
  settled_.Reset();  // the actuator may have been moved while it was not ours
  activated_ = std::chrono::steady_clock::now();
}

std::string PyTransfer::ExecuteText(std::span<const double> commands) const {
  return fmt::format("execute({} {})", FormatLengths(commands), units_.length_name);
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
