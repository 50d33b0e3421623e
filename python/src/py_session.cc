// See py_session.h.
#include "py_session.h"

#include <fmt/core.h>
#include <pybind11/numpy.h>

#include <filesystem>
#include <utility>

#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::python {
namespace {

// A read-only float64 view of `values`, no copy.
py::array View(std::span<const double> values) {
  py::array_t<double> a({static_cast<py::ssize_t>(values.size())},
                        {static_cast<py::ssize_t>(sizeof(double))}, values.data(), py::none());
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

const char* KindName(runner::RowKind kind) {
  switch (kind) {
    case runner::RowKind::kCommitted: return "committed";
    case runner::RowKind::kIntermediate: return "intermediate";
    case runner::RowKind::kUncommitted: return "uncommitted";
  }
  return "";
}

// Calls `f(args...)` with the GIL; a Python exception stops the run as an Error.
template <typename... Args>
void CallObserver(const SharedPy& f, const char* what, Args&&... args) {
  py::gil_scoped_acquire gil;
  try {
    f->get()(std::forward<Args>(args)...);
  } catch (py::error_already_set& e) {
    const std::string described = InterruptOrDescribe(
        e, fmt::format("a Python observer's {}", what),
        "the run holds; every committed step is kept");
    throw Error(fmt::format("a Python observer's {} raised {}", what, described));
  }
}

SharedPy Method(const py::object& o, const char* name) {
  if (!py::hasattr(o, name)) return nullptr;
  return std::make_shared<SharedObject>(o.attr(name));
}

int SlotIndex(const io::RunSpec& spec, const std::string& slot, const char* argument) {
  std::string names;
  for (std::size_t i = 0; i < spec.substructures.size(); ++i) {
    if (spec.substructures[i].slot == slot) return static_cast<int>(i);
    names += (names.empty() ? "" : ", ") + spec.substructures[i].slot;
  }
  throw ConfigError(fmt::format("{}[\"{}\"]: the {} model has no such slot; its slots are: {}",
                                argument, slot, spec.model.name, names));
}

}  // namespace

// See py_session.h.
void Substitute(io::RunSpec& spec, const py::dict& transfers, const py::dict& laws,
                const DriverCauseSlot& cause) {
  for (const auto& [key, value] : transfers) {
    const std::string slot = py::str(key);
    auto& sub = spec.substructures[static_cast<std::size_t>(SlotIndex(spec, slot, "transfers"))];
    if (!sub.physical) {
      throw ConfigError(fmt::format(
          "transfers[\"{}\"]: slot {} is numerical in the config; a transfer system serves a "
          "physical slot: declare it under substructures.{} with type: physical (setup, "
          "safety)", slot, slot, slot));
    }
    auto driver = std::make_shared<SharedObject>(py::reinterpret_borrow<py::object>(value));
    // One limit set per actuator: a specimen on n actuators gets a driver of n (execute
    // receives an array of n commands).
    const std::vector<transfer::SafetyLimits> limits = sub.ActuatorLimits();
    PyTransfer check(driver, slot, limits);  // the methods and units, before anything is built
    sub.physical->transfer = {"python", [driver, slot, limits, cause] {
                                return std::make_unique<PyTransfer>(driver, slot, limits, cause);
                              }};
  }
  for (const auto& [key, value] : laws) {
    const std::string slot = py::str(key);
    auto& sub = spec.substructures[static_cast<std::size_t>(SlotIndex(spec, slot, "laws"))];
    auto law = std::make_shared<SharedObject>(py::reinterpret_borrow<py::object>(value));
    sub = substructures::NumericalSpec(slot, std::make_unique<PyLaw>(law, slot));
  }
}

PyObserver::PyObserver(py::object observer, const std::vector<std::string>& actuators)
    : actuators_(static_cast<py::ssize_t>(actuators.size())) {
  for (std::size_t k = 0; k < actuators.size(); ++k) actuators_[k] = py::str(actuators[k]);
  py::list fields;
  for (const char* name : {"command", "position", "force", "lab_time"}) {
    fields.append(py::make_tuple(name, "f8"));
  }
  exchange_type_ = py::module_::import("numpy").attr("dtype")(fields);
  on_commit_ = Method(observer, "on_commit");
  on_trial_ = Method(observer, "on_trial");
  on_stop_ = Method(observer, "on_stop");
  if (!on_commit_ && !on_trial_ && !on_stop_) {
    if (!PyCallable_Check(observer.ptr())) {
      throw ConfigError(fmt::format("observer {}: expected a callable (called with each commit) "
                                    "or an object with on_commit, on_trial or on_stop",
                                    std::string(py::repr(observer))));
    }
    on_commit_ = std::make_shared<SharedObject>(observer);
  }
}

void PyObserver::OnCommit(const runner::CommitEvent& e) {
  if (!on_commit_) return;
  py::gil_scoped_acquire gil;
  py::dict c;
  c["kind"] = KindName(e.kind);
  c["step"] = e.step;
  c["t"] = e.t;
  c["x"] = View(e.x);
  c["r"] = View(e.r);
  c["row"] = View(e.row);
  CallObserver(on_commit_, "on_commit", py::module_::import("types").attr("SimpleNamespace")(**c));
}

void PyObserver::OnTrial(const runner::TrialEvent& e) {
  if (!on_trial_) return;
  py::gil_scoped_acquire gil;
  py::dict c;
  c["step"] = e.at.step;
  c["stage"] = e.at.stage;
  c["t"] = e.at.t;
  c["d"] = View(e.d);
  c["r"] = View(e.r);
  // One record per actuator, named in `actuators`: command [m], position [m], force [N], lab
  // time [s] (fields of a numpy structured array).
  const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(e.exchanges.size())};
  const py::array ex(py::dtype::from_args(exchange_type_), shape);
  auto* w = static_cast<double*>(ex.request().ptr);
  for (std::size_t i = 0; i < e.exchanges.size(); ++i) {
    const auto& x = e.exchanges[i];
    w[4 * i + 0] = x.command;
    w[4 * i + 1] = x.position;
    w[4 * i + 2] = x.force;
    w[4 * i + 3] = x.lab_time;
  }
  c["exchanges"] = ex;
  c["actuators"] = actuators_;
  CallObserver(on_trial_, "on_trial", py::module_::import("types").attr("SimpleNamespace")(**c));
}

void PyObserver::OnStop(const runner::StopEvent& e) {
  if (!on_stop_) return;
  CallObserver(on_stop_, "on_stop", runner::StatusName(e.status), e.reason);
}

PySession::PySession(const SessionArguments& args) {
  if (args.resume) {
    StartResume(args);
    return;
  }
  if (args.config.is_none()) {
    throw ConfigError("Session(): give a config (a run-config path or a dict), or resume=CSV");
  }
  if (args.command != "run" && args.command != "simulate") {
    throw ConfigError(fmt::format("command \"{}\": expected \"run\" or \"simulate\"",
                                  args.command));
  }
  // The config: a file, or a dict with the same keys (as JSON text, which is YAML).
  const bool from_dict = py::isinstance<py::dict>(args.config);
  io::SimulationConfig cfg =
      from_dict ? io::ParseSimulationConfig(YamlInput::FromText(
                      py::str(py::module_::import("json").attr("dumps")(args.config,
                                                                         py::arg("indent") = 2)),
                      "<config dict>"))
                : io::LoadSimulationConfig(py::str(py::module_::import("os").attr("fspath")(
                      args.config)));
  io::SubstructureOptions options;
  options.allow_physical = args.command == "run";
  options.physical_hint = "simulate() is numerical only: use hybridtest.run() for a hybrid test";
  if (args.command == "simulate" && py::len(args.transfers) > 0) {
    throw ConfigError("simulate(): transfers are for a hybrid test: use hybridtest.run()");
  }
  io::RunSpec spec = io::CompileRunSpec(cfg, options);
  // A `real_time:` run is paced by the Session on the clock the spec names, or this one (the
  // Session refuses a clock without the block).
  if (args.clock) spec.real_time.clock = *args.clock;
  Substitute(spec, args.transfers, args.laws, cause_);
  spec.output.command = args.command;
  spec.output.files = args.out.has_value();
  if (args.out) spec.output.csv_path = *args.out;
  // The front door, as the command line's: lock, output guards, disk budget, input record
  // (what the compile read: a dict config is no file, its model and bench files are),
  // provenance. Nothing is built or activated before it.
  runner::OpenedRun opened = runner::OpenRun(
      spec, {.overwrite = args.overwrite,
             .command_line = fmt::format("python: hybridtest.{}(...)", args.command)});
  channels_ = runner::JournalChannels(spec);
  // The session holds the run's lock until it is closed.
  session_ = std::make_unique<runner::Session>(std::move(spec), std::move(opened));
  session_->AddObserver(recorder_);
}

PySession::~PySession() { session_.reset(); }

void PySession::Close() {
  RefuseReentry("close()");
  session_.reset();  // and the run's lock with it
}

// A call that changes the run, made from inside one of the run's own Python callbacks (the
// C++ step is on the stack below it): refused, and the run stops after the step in progress.
void PySession::RefuseReentry(const char* call) {
  if (!advancing_) return;
  const InCallback* inside = CurrentCallback();
  reentry_ = fmt::format(
      "Session.{} called from inside {}: a run's own callbacks may not step, run or close it "
      "(the step in progress would be re-entered: a duplicate row, or a run freed under its "
      "own feet). The run stops, the bench holds and every committed row is kept; to stop a "
      "run from a bench driver or an observer, raise an exception or call request_stop()",
      call, inside != nullptr ? inside->Describe()
                              : std::string("one of the run's own Python callbacks (a bench "
                                            "driver, a law or an observer), or from another "
                                            "thread while the run steps"));
  session_->RequestStop();  // should the callback swallow the error
  throw Error(*reentry_);
}

runner::Session& PySession::session() const {
  if (!session_) throw ConfigError("this Session is closed: make a new one");
  return *session_;
}

void PySession::AddObserver(py::object observer) {
  RefuseReentry("add_observer()");
  if (initialized_) {
    throw ConfigError("add_observer(): add observers before initialize(), step() or run()");
  }
  std::vector<std::string> actuators;
  for (const auto& sub : session().spec().substructures) {
    for (const std::string& name : sub.ActuatorNames()) actuators.push_back(name);
  }
  observers_.push_back(std::make_unique<PyObserver>(std::move(observer), actuators));
  session().AddObserver(*observers_.back());
}

bool PySession::done() const {
  if (!session_) return true;  // closed: the record is final
  return initialized_ && session().result().status != runner::SessionStatus::kWorking;
}

runner::StepResult PySession::AdvanceWith(
    const std::function<runner::StepResult(runner::Session&)>& call) {
  runner::Session& s = session();
  runner::StepResult result;
  {
    advancing_ = true;
    struct Advancing {  // false again however the step ends
      bool& flag;
      ~Advancing() { flag = false; }
    } advancing{advancing_};
    py::gil_scoped_release release;
    result = call(s);
  }
  initialized_ = true;
  // What a callback raised for the caller (KeyboardInterrupt), or a refused re-entry: raised
  // as itself, the run already held and stopped.
  if (std::optional<py::error_already_set> kept = TakeKeptForCaller()) throw std::move(*kept);
  if (reentry_) throw Error(*std::exchange(reentry_, std::nullopt));
  return result;
}

std::string PySession::Advance(bool initialize) {
  return runner::StatusName(AdvanceWith([initialize](runner::Session& s) {
                              return initialize ? s.Initialize() : s.Step();
                            }).status);
}

std::string PySession::Initialize() {
  RefuseReentry("initialize()");
  return Advance(true);
}

std::string PySession::Step() {
  RefuseReentry("step()");
  if (initialized_ && session().paced_loop() != nullptr) {
    throw ConfigError(
        "Session.step(): a real-time run (real_time:) is paced by run(), one step per tick of "
        "its clock; call run() (initialize() first if you like)");
  }
  return Advance(!initialized_);
}

std::string PySession::Run() {
  RefuseReentry("run()");
  runner::Session& s = session();
  // The Session's one loop, paced on a real-time run; Ctrl-C is checked between two steps
  // (with the GIL): the run holds there, every committed step kept, and KeyboardInterrupt is
  // raised.
  std::optional<py::error_already_set> interrupt;
  s.SetBetweenSteps([&interrupt](runner::Session& session) {
    const py::gil_scoped_acquire gil;
    if (!interrupt && PyErr_CheckSignals() != 0) {
      interrupt.emplace();  // fetched
      return session.InterruptBetweenSteps();
    }
    return session.result();
  });
  struct Unhook {  // the hook refers to this frame
    runner::Session& session;
    ~Unhook() { session.SetBetweenSteps({}); }
  } unhook{s};
  const runner::StepResult result =
      AdvanceWith([](runner::Session& session) { return session.Run(); });
  if (interrupt) throw *interrupt;
  return runner::StatusName(result.status);
}

void PySession::RaiseError() const {
  const std::exception_ptr e = session().error();
  if (!e) return;
  if (!cause_->exception) std::rethrow_exception(e);
  // The driver's own exception as the cause of the error it stopped the run with (its
  // traceback shows where in the driver it was raised).
  SetPythonError(e);
  py::error_already_set raised;
  PyException_SetCause(raised.value().ptr(), cause_->exception->get().inc_ref().ptr());
  throw raised;
}

}  // namespace hybridtest::python
