// hybridtest._core.read_run: a run's journal (or stage record) and its sidecar, as written by
// `hybridtest run`, `simulate`, `resume` or a Python session with `out`.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "hybridtest/io/run_reader.h"

namespace hybridtest::python {

void BindReadRun(py::module_& m) {
  m.def(
      "read_run",
      [](const std::string& csv_path) {
        io::RunData run = io::LoadRun(csv_path);
        py::list channels;
        for (const auto& c : run.channels) {
          channels.append(py::make_tuple(c.name, run.Unit(c.name), run.Description(c.name)));
        }
        py::dict out;
        out["channels"] = channels;
        // (rows × channels), column-major: each channel is a contiguous column; moved, not copied.
        out["values"] = py::cast(std::move(run.values), py::return_value_policy::move);
        out["metadata"] = run.metadata.is_null()
                              ? py::object(py::none())
                              : py::module_::import("json").attr("loads")(run.metadata.dump());
        out["warnings"] = run.warnings;
        return out;
      },
      py::arg("csv_path"),
      "{channels: [(name, unit, description)], values: (rows × channels), metadata: the "
      "sidecar or None, warnings}");
}

}  // namespace hybridtest::python
