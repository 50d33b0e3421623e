// hybridtest.Model: a built model (a built-in or a model file) and the Kane engine's functions
// at a given (t, x, r). Inputs are float64 numpy arrays (read in place when contiguous);
// results are new arrays that own the engine's result (moved, not copied).
//
//   x = [q; u; z] (num_states = 2n + nz), SI; r one restoring force per slot [N] (or [N·m]);
//   without r, each slot's default numerical spring gives r = k_s · d_s(t, q).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <memory>
#include <optional>
#include <random>

#include "bindings.h"
#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::python {
namespace {

using Vector = Eigen::Ref<const Eigen::VectorXd>;

// Overrides from a {name: value} dict; unknown names are ConfigErrors listing the known ones.
void Override(models::ParameterSet& set, const std::optional<py::dict>& parameters,
              const std::string& where) {
  if (!parameters) return;
  for (const auto& [key, value] : *parameters) {
    const std::string name = py::str(key);
    set.Set(name, value.cast<double>(), where + ": parameters." + name);
  }
}

class PyModel {
 public:
  explicit PyModel(models::BuiltModel built)
      : built_(std::make_shared<models::BuiltModel>(std::move(built))), data_(built_->model) {}

  static PyModel FromFile(const std::filesystem::path& file_path,
                          const std::optional<py::dict>& parameters) {
    const std::string path = file_path.string();
    const modelfile::ModelFile file = modelfile::LoadModelFile(path);
    models::ParameterSet set = file.parameters;
    Override(set, parameters, path);
    return PyModel(modelfile::BuildModelFile(file, set));
  }
  // `blades` (a number: 2.5 and 10**9 reach the shared bound and are refused by it).
  static PyModel Builtin(const std::string& name, double given,
                         const std::optional<py::dict>& parameters) {
    const int blades =
        name == "rotor" ? models::CheckRotorBlades(given, "Model.builtin('rotor').blades") : 0;
    models::ParameterSet set = models::DefaultParameters(name, blades);
    Override(set, parameters, "Model.builtin(" + name + ")");
    return PyModel(models::BuildModel(name, blades, set));
  }

  const multibody::Model& model() const { return built_->model; }
  const models::BuiltModel& built() const { return *built_; }

  Eigen::MatrixXd MassMatrix(double t, const Vector& x) {
    Kinematics(t, x);
    multibody::CalcMassMatrix<double>(model(), data_);
    return data_.M;
  }
  Eigen::VectorXd Forcing(double t, const Vector& x, const std::optional<Eigen::VectorXd>& r) {
    const Eigen::VectorXd rr = Restoring(t, x, r);
    Kinematics(t, x);
    multibody::CalcForcing<double>(model(), data_, rr);
    return data_.g;
  }
  Eigen::VectorXd StateDerivative(double t, const Vector& x,
                                  const std::optional<Eigen::VectorXd>& r) {
    const Eigen::VectorXd rr = Restoring(t, x, r);
    Eigen::VectorXd xdot(model().num_states());
    multibody::CalcStateDerivative<double>(model(), data_, t, x, rr, xdot);
    return xdot;
  }
  Eigen::MatrixXd StateJacobian(double t, const Vector& x,
                                const std::optional<Eigen::VectorXd>& r) {
    const Eigen::VectorXd rr = Restoring(t, x, r);
    return multibody::CalcStateJacobian(model(), t, CheckState(x), rr);
  }
  Eigen::MatrixXd CouplingMatrix(double t, const Vector& x) {
    return multibody::CalcCouplingMatrix(model(), t, CheckState(x));
  }
  Eigen::VectorXd SlotDisplacements(double t, const Vector& x) {
    CheckState(x);
    Eigen::VectorXd d(model().num_slots());
    multibody::CalcSlotDisplacements<double>(model(), data_, t, x.head(model().num_coordinates()),
                                             d);
    return d;
  }

  // What `hybridtest check-model` checks without SymPy: M symmetric positive definite and g
  // finite at `states` random states. Throws ModelError naming the first state that fails.
  py::dict Check(int states, unsigned seed) {
    const multibody::Model& m = model();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double worst = 1.0;
    Eigen::VectorXd x(m.num_states()), r(m.num_slots());
    for (int i = 0; i < states; ++i) {
      const int n = m.num_coordinates();
      for (int k = 0; k < n; ++k) {
        x(k) = (m.coordinates()[k].unit == "rad" ? 1.0 : 0.1) * unit(rng);
        x(n + k) = unit(rng);
      }
      for (int k = 2 * n; k < m.num_states(); ++k) x(k) = unit(rng);
      for (int s = 0; s < m.num_slots(); ++s) r(s) = 100.0 * unit(rng);
      const double t = 2.0 * std::abs(unit(rng));
      multibody::CalcKinematics<double>(m, data_, t, x);
      multibody::CalcMassMatrix<double>(m, data_);
      multibody::CalcForcing<double>(m, data_, r);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(data_.M);
      const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
      if (!(lo > 1e-12 * hi) || !data_.g.allFinite() ||
          !(data_.M - data_.M.transpose()).isZero(1e-12 * hi)) {
        throw ModelError(fmt::format(
            "model {}: at random state {} (t = {} s) M is not symmetric positive definite or g "
            "is not finite (eigenvalues of M in [{:g}, {:g}]): check the masses and the "
            "coordinates", built_->name, i, t, lo, hi));
      }
      worst = std::max(worst, hi / lo);
    }
    py::dict out;
    out["states"] = states;
    out["mass_matrix_positive_definite"] = true;
    out["worst_condition_number"] = worst;
    return out;
  }

 private:
  const Eigen::VectorXd& CheckState(const Vector& x) {
    if (x.size() != model().num_states()) {
      const int n = model().num_coordinates();
      throw ConfigError(fmt::format(
          "x has {} values; the {} model needs {} (x = [q; u{}] with n = {}): give a float "
          "array of length {}", x.size(), built_->name, model().num_states(),
          model().num_extra_states() > 0 ? "; z" : "", n, model().num_states()));
    }
    x_ = x;
    return x_;
  }
  void Kinematics(double t, const Vector& x) {
    multibody::CalcKinematics<double>(model(), data_, t, CheckState(x));
  }
  Eigen::VectorXd Restoring(double t, const Vector& x, const std::optional<Eigen::VectorXd>& r) {
    const int m = model().num_slots();
    if (r) {
      if (r->size() != m) {
        throw ConfigError(fmt::format("r has {} values; the {} model has {} restoring-force "
                                      "slots: give one force per slot [N]", r->size(),
                                      built_->name, m));
      }
      return *r;
    }
    Eigen::VectorXd d = SlotDisplacements(t, x);
    for (int s = 0; s < m; ++s) d(s) *= built_->slot_stiffness[static_cast<std::size_t>(s)];
    return d;
  }

  std::shared_ptr<models::BuiltModel> built_;
  multibody::Data<double> data_;
  Eigen::VectorXd x_;
};

py::list Quantities(const std::vector<multibody::QuantityInfo>& infos) {
  py::list out;
  for (const auto& q : infos) out.append(py::make_tuple(q.name, q.unit, q.description));
  return out;
}

}  // namespace

void BindModel(py::module_& m) {
  py::class_<PyModel>(m, "Model", "A multibody model (Kane's method): M(q) u̇ = g(t, x, r).")
      .def_static("from_file", &PyModel::FromFile, py::arg("path"),
                  py::arg("parameters") = py::none(),
                  "Loads a model file (docs/model-files.md); `parameters` overrides {name: SI "
                  "value}.")
      .def_static("builtin", &PyModel::Builtin, py::arg("name"), py::arg("blades") = 3.0,
                  py::arg("parameters") = py::none(),
                  "A built-in model: rotor (blades), double_pendulum, spinning_top.")
      .def_property_readonly("name", [](const PyModel& p) { return p.built().name; })
      .def_property_readonly("description",
                             [](const PyModel& p) { return p.built().description; })
      .def_property_readonly("num_coordinates",
                             [](const PyModel& p) { return p.model().num_coordinates(); })
      .def_property_readonly("num_states", [](const PyModel& p) { return p.model().num_states(); })
      .def_property_readonly("num_slots", [](const PyModel& p) { return p.model().num_slots(); })
      .def_property_readonly("coordinates",
                             [](const PyModel& p) { return Quantities(p.model().coordinates()); },
                             "[(name, unit, description)] of q")
      .def_property_readonly("speeds",
                             [](const PyModel& p) { return Quantities(p.model().speeds()); })
      .def_property_readonly("slots",
                             [](const PyModel& p) {
                               py::list out;
                               for (const auto& s : p.model().slots()) {
                                 out.append(py::make_tuple(s.info.name, s.info.unit,
                                                           s.info.description));
                               }
                               return out;
                             })
      .def_property_readonly("slot_stiffness",
                             [](const PyModel& p) { return p.built().slot_stiffness; },
                             "default numerical stiffness per slot [N/m] (or [N·m/rad])")
      .def_property_readonly("parameters",
                             [](const PyModel& p) {
                               py::dict out;
                               for (const auto& q : p.built().parameters.all()) {
                                 out[py::str(q.name)] =
                                     py::make_tuple(q.value, q.unit, q.description);
                               }
                               return out;
                             },
                             "{name: (value SI, unit, description)}")
      .def("mass_matrix", &PyModel::MassMatrix, py::arg("t"), py::arg("x"),
           "M(q) (n × n), SymPy's convention M u̇ = forcing")
      .def("forcing", &PyModel::Forcing, py::arg("t"), py::arg("x"), py::arg("r") = py::none(),
           "g(t, x, r) (n)")
      .def("state_derivative", &PyModel::StateDerivative, py::arg("t"), py::arg("x"),
           py::arg("r") = py::none(), "ẋ = f_rhs(t, x, r) (num_states)")
      .def("state_jacobian", &PyModel::StateJacobian, py::arg("t"), py::arg("x"),
           py::arg("r") = py::none(), "∂f_rhs/∂x (num_states × num_states), exact")
      .def("coupling_matrix", &PyModel::CouplingMatrix, py::arg("t"), py::arg("x"),
           "B = ∂g/∂r (n × num_slots), exact")
      .def("slot_displacements", &PyModel::SlotDisplacements, py::arg("t"), py::arg("x"),
           "d (num_slots) [m] (or [rad])")
      .def("check", &PyModel::Check, py::arg("states") = 20, py::arg("seed") = 1u,
           "M symmetric positive definite and g finite at random states (as check-model)")
      .def("__repr__", [](const PyModel& p) {
        return fmt::format("<hybridtest.Model {}: n = {}, {} slots>", p.built().name,
                           p.model().num_coordinates(), p.model().num_slots());
      });
}

}  // namespace hybridtest::python
