// The Python face of PySession (py_session.h): hybridtest.Session.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "py_session.h"

namespace hybridtest::python {
namespace {

py::object JsonToPython(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// The recorded rows (rows × channels). A finished, held or stopped run adds no row any more:
// a read-only view of the record, kept alive by the session object. A run still working: a copy.
py::array Values(py::object self) {
  const PySession& s = self.cast<const PySession&>();
  const auto& v = s.recorder().values();
  const py::ssize_t rows = s.recorder().rows();
  const auto cols = static_cast<py::ssize_t>(s.channels().size());
  const std::vector<py::ssize_t> shape{rows, cols};
  const std::vector<py::ssize_t> strides{
      static_cast<py::ssize_t>(cols * static_cast<py::ssize_t>(sizeof(double))),
      static_cast<py::ssize_t>(sizeof(double))};
  if (!s.done()) return py::array_t<double>(shape, strides, v.data());
  py::array_t<double> a(shape, strides, v.data(), self);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

}  // namespace

void BindSession(py::module_& m) {
  py::class_<PySession>(m, "Session",
                        "A run (hybrid test or simulation) stepped from Python (decision 0014).")
      .def(py::init([](py::object config, py::dict transfers, py::dict laws,
                       std::optional<std::string> out, bool overwrite, std::string command,
                       std::optional<std::string> resume, bool after_safety_stop,
                       std::optional<double> force_tolerance,
                       std::optional<double> position_tolerance, std::vector<std::string> set,
                       std::optional<std::string> clock) {
             SessionArguments args{std::move(config), std::move(transfers), std::move(laws),
                                   std::move(out), overwrite, std::move(command), std::nullopt,
                                   std::move(clock)};
             if (resume) {
               args.resume = ResumeArguments{*resume, after_safety_stop, force_tolerance,
                                             position_tolerance, std::move(set)};
             }
             return std::make_unique<PySession>(args);
           }),
           py::arg("config") = py::none(), py::kw_only(), py::arg("transfers") = py::dict(),
           py::arg("laws") = py::dict(), py::arg("out") = py::none(),
           py::arg("overwrite") = false, py::arg("command") = "run",
           py::arg("resume") = py::none(), py::arg("after_safety_stop") = false,
           py::arg("force_tolerance") = py::none(), py::arg("position_tolerance") = py::none(),
           py::arg("set") = std::vector<std::string>{}, py::arg("clock") = py::none())
      .def("add_observer", &PySession::AddObserver, py::arg("observer"))
      .def("initialize", &PySession::Initialize,
           "Activates the substructures and commits row 0; returns the status")
      .def("step", &PySession::Step, "One committed step; returns the status")
      .def("run", &PySession::Run, "Steps until the run is no longer working; returns the status")
      .def("request_stop", &PySession::RequestStop)
      .def("raise_error", &PySession::RaiseError,
           "Raises the failure that stopped the run, if any")
      .def("close", &PySession::Close, "Releases the run (its files and lock)")
      .def_property_readonly("status",
                             [](const PySession& s) {
                               return runner::StatusName(s.session().result().status);
                             })
      .def_property_readonly("reason",
                             [](const PySession& s) { return s.session().result().reason; })
      .def_property_readonly("statistics",
                             [](const PySession& s) {
                               return JsonToPython(runner::ToJson(s.session().statistics()));
                             })
      .def_property_readonly("channels",
                             [](const PySession& s) {
                               py::list out;
                               for (const auto& c : s.channels()) {
                                 out.append(py::make_tuple(c.name, c.unit, c.description));
                               }
                               return out;
                             },
                             "[(name, unit, description)] of the journal's columns")
      .def_property_readonly("t", [](const PySession& s) { return s.session().committed().t; },
                             "time of the last committed point [s]")
      .def_property_readonly("x",
                             [](const PySession& s) -> Eigen::VectorXd {
                               return s.session().committed().x;
                             },
                             "state [q; u; z] of the last committed point (a copy)")
      .def_property_readonly("notes", &PySession::notes,
                             "what a resume repaired on the way (e.g. a staged sidecar)")
      .def_property_readonly("values", &Values, "the recorded rows (rows × channels), SI")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PySession& s, py::args) { s.Close(); });
}

}  // namespace hybridtest::python
