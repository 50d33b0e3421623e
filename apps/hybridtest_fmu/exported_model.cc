// See exported_model.h.
#include "exported_model.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::fmu_export {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError(fmt::format("the exported FMU has no {}: its resources folder is "
                                  "incomplete; export it again with hybridtest export-fmu",
                                  path.string()));
  }
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The exported slots of one block: r = f + K0 (d − d_c), from the feed (exported_model.h).
class FedSlots final : public substructures::Substructure {
 public:
  FedSlots(std::shared_ptr<const Feed> feed, std::vector<int> feed_index, Eigen::MatrixXd k0)
      : feed_(std::move(feed)), index_(std::move(feed_index)), k0_(std::move(k0)) {}
  int num_slots() const override { return static_cast<int>(index_.size()); }
  void Trial(std::span<const double> d, std::span<double> r,
             const substructures::TrialContext& /*context*/) override {
    const int m = num_slots();
    for (int i = 0; i < m; ++i) {
      double ri = feed_->force(index_[i]);
      for (int j = 0; j < m; ++j) ri += k0_(i, j) * (d[j] - feed_->about(index_[j]));
      r[i] = ri;
    }
  }
  void Commit() override {}
  std::string Describe() const override { return "served by the co-simulation master (FMU input)"; }
  std::optional<Eigen::MatrixXd> initial_stiffness() const override { return k0_; }

 private:
  std::shared_ptr<const Feed> feed_;
  std::vector<int> index_;
  Eigen::MatrixXd k0_;
};

}  // namespace

ExportedModel::ExportedModel(const std::string& resources) {
  const fs::path dir = fs::path(resources) / "hybridtest";
  const nlohmann::json settings = nlohmann::json::parse(ReadText(dir / "export.json"));
  config_path_ = (dir / settings.at("config").get<std::string>()).string();
  config_text_ = ReadText(config_path_);
  const io::RunSpec spec = Compile();
  layout_ = MakeLayout(spec, BlocksFromJson(settings.at("blocks")));
  for (const auto& v : layout_.variables) values_.push_back(v.start);
  parameter_set_.assign(spec.model.parameters.all().size(), false);
  const auto& slots = spec.model.model.slots();
  for (const auto& name : layout_.slots) {
    for (int i = 0; i < static_cast<int>(slots.size()); ++i) {
      if (slots[i].info.name == name) slot_of_.push_back(i);
    }
  }
  feed_ = std::make_shared<Feed>();
  feed_->force = Eigen::VectorXd::Zero(static_cast<long>(slot_of_.size()));
  feed_->about = feed_->force;
}

ExportedModel::~ExportedModel() = default;

void ExportedModel::SetupExperiment(double start, std::optional<double> stop) {
  if (std::abs(start) > 0.0) {
    throw ConfigError(fmt::format("start time {} s: an exported hybridtest model starts at "
                                  "t = 0 (its initial state and loads are given there)", start));
  }
  stop_ = stop;
}

void ExportedModel::Set(unsigned vr, double value) {
  if (vr >= values_.size()) throw Error(fmt::format("no variable has value reference {}", vr));
  const Variable& v = layout_.variables[vr];
  if (v.kind == Variable::Kind::kParameter) {
    if (initialized_) {
      throw Error(fmt::format("parameter {} is fixed after initialization", v.name));
    }
    parameter_set_[v.index] = true;
  } else if (v.kind != Variable::Kind::kInput) {
    throw Error(fmt::format("{} is an output: it cannot be set", v.name));
  }
  if (!std::isfinite(value)) throw Error(fmt::format("{} = {} is not finite", v.name, value));
  values_[vr] = value;
}

double ExportedModel::Get(unsigned vr) const {
  if (vr >= values_.size()) throw Error(fmt::format("no variable has value reference {}", vr));
  return values_[vr];
}

io::RunSpec ExportedModel::Compile() const {
  YAML::Node root = YAML::Load(config_text_);
  for (std::size_t k = 0; k < parameter_set_.size(); ++k) {
    if (!parameter_set_[k]) continue;
    for (std::size_t vr = 0; vr < layout_.variables.size(); ++vr) {
      const Variable& v = layout_.variables[vr];
      if (v.kind == Variable::Kind::kParameter && v.index == static_cast<int>(k)) {
        root["model"]["parameters"][v.name] = fmt::format("{:.17g}", values_[vr]);
      }
    }
  }
  YAML::Emitter out;
  out << root;
  const io::SimulationConfig cfg =
      io::ParseSimulationConfig(YamlInput::FromText(out.c_str(), config_path_));
  io::RunSpec spec = io::CompileRunSpec(cfg);
  spec.output.files = false;
  spec.output.command = "fmu";
  spec.quiet = true;
  return spec;
}

std::unique_ptr<runner::Session> ExportedModel::NewSession() const {
  io::RunSpec spec = Compile();
  const double dt = spec.scheme.dt;
  long steps = io::kMaxSteps / 2;
  if (stop_) steps = std::max(1L, static_cast<long>(std::ceil(*stop_ / dt - 1e-9)));
  spec.scheme.steps = steps;
  spec.scheme.duration = static_cast<double>(steps) * dt;
  std::size_t first = 0;
  for (const auto& block : layout_.blocks) {
    std::vector<int> index;
    std::vector<std::string> slots;
    for (std::size_t i = 0; i < block.slots.size(); ++i) index.push_back(static_cast<int>(first + i));
    const long m = static_cast<long>(block.slots.size());
    Eigen::MatrixXd k0 = Eigen::MatrixXd::Zero(m, m);
    for (long i = 0; i < m; ++i) {
      for (long j = 0; j < m; ++j) k0(i, j) = block.k0.at(i).at(j);
    }
    substructures::SubstructureSpec fed;
    fed.slot = block.slots.size() == 1 ? block.slots[0] : "fmu_block_" + block.slots[0];
    if (block.slots.size() > 1) fed.slots = block.slots;
    const std::shared_ptr<const Feed> feed = feed_;
    fed.custom = [feed, index, k0] { return std::make_unique<FedSlots>(feed, index, k0); };
    // Replace the model's default specs of these slots by the fed one, in slot order.
    auto& specs = spec.substructures;
    std::size_t at = specs.size();
    for (std::size_t s = 0; s < specs.size();) {
      const auto names = specs[s].SlotNames();
      if (std::find(block.slots.begin(), block.slots.end(), names.at(0)) != block.slots.end()) {
        at = std::min(at, s);
        specs.erase(specs.begin() + static_cast<long>(s));
      } else {
        ++s;
      }
    }
    specs.insert(specs.begin() + static_cast<long>(at), std::move(fed));
    first += block.slots.size();
  }
  return std::make_unique<runner::Session>(std::move(spec));
}

void ExportedModel::Check(const runner::StepResult& result, const std::string& what) const {
  if (result.status == runner::SessionStatus::kWorking ||
      result.status == runner::SessionStatus::kFinished) {
    return;
  }
  throw Error(fmt::format("{} failed at t = {} s: {}", what, t_, result.reason));
}

void ExportedModel::Initialize() {
  for (std::size_t vr = 0; vr < layout_.variables.size(); ++vr) {
    const Variable& v = layout_.variables[vr];
    if (v.kind == Variable::Kind::kInput) feed_->force(v.index) = values_[vr];
  }
  spec_.emplace(Compile());
  // d_c at t = 0: the initial state's slot displacements.
  multibody::Data<double> data(spec_->model.model);
  Eigen::VectorXd d(spec_->model.model.num_slots());
  const long n = spec_->model.model.num_coordinates();
  CalcSlotDisplacements<double>(spec_->model.model, data, 0.0, spec_->x0.head(n), d);
  for (std::size_t k = 0; k < slot_of_.size(); ++k) feed_->about(static_cast<long>(k)) = d(slot_of_[k]);
  session_ = NewSession();
  Check(session_->Initialize(), "initialization");
  initialized_ = true;
  t_ = 0.0;
  ReadOutputs();
}

void ExportedModel::ReadOutputs() {
  const auto& point = session_->committed();
  const auto& model = spec_->model.model;
  const long n = model.num_coordinates();
  multibody::Data<double> data(model);
  Eigen::VectorXd d(model.num_slots());
  CalcSlotDisplacements<double>(model, data, point.t, point.x.head(n), d);
  for (std::size_t vr = 0; vr < layout_.variables.size(); ++vr) {
    const Variable& v = layout_.variables[vr];
    switch (v.kind) {
      case Variable::Kind::kDisplacement: values_[vr] = d(slot_of_[v.index]); break;
      case Variable::Kind::kCoordinate: values_[vr] = point.x(v.index); break;
      case Variable::Kind::kSpeed: values_[vr] = point.x(n + v.index); break;
      default: break;
    }
  }
}

void ExportedModel::DoStep(double t, double h) {
  if (!initialized_) throw Error("DoStep before the end of initialization");
  const double dt = spec_->scheme.dt;
  if (std::abs(t - t_) > 1e-9 * std::max(1.0, std::abs(t))) {
    throw Error(fmt::format("DoStep at t = {} s, but the FMU is at t = {} s", t, t_));
  }
  const long steps = std::lround(h / dt);
  if (steps < 1 || std::abs(static_cast<double>(steps) * dt - h) > 1e-9 * h) {
    throw Error(fmt::format("communication step {} s is not a whole number of the scheme's "
                            "steps dt = {} s; step the FMU by multiples of dt", h, dt));
  }
  for (std::size_t vr = 0; vr < layout_.variables.size(); ++vr) {
    const Variable& v = layout_.variables[vr];
    if (v.kind == Variable::Kind::kInput) feed_->force(v.index) = values_[vr];
    if (v.kind == Variable::Kind::kDisplacement) feed_->about(v.index) = values_[vr];
  }
  for (long k = 0; k < steps; ++k) {
    if (session_->result().status == runner::SessionStatus::kFinished) {
      throw Error(fmt::format("the FMU reached its stop time {} s", t_));
    }
    Check(session_->Step(), "the step");
  }
  t_ = session_->committed().t;
  ReadOutputs();
}

std::string ExportedModel::SaveState() const {
  if (!initialized_) throw Error("the FMU state is defined after initialization only");
  // A run state without a journal: the counts the file observer would fill (rows committed,
  // none on disk) so that it reads back as a consistent state.
  runner::RunState state = session_->GetState();
  const auto& point = session_->committed();
  state.rows = std::max(state.rows, point.step + 1);
  state.journal_rows = 0;
  state.journal_last_row.reset();
  if (state.row.empty()) {
    state.row.push_back(point.t);
    state.row.insert(state.row.end(), point.x.data(), point.x.data() + point.x.size());
    state.row.insert(state.row.end(), point.r.data(), point.r.data() + point.r.size());
  }
  nlohmann::json j{{"run_state", runner::ToJson(state)},
                   {"values", values_},
                   {"force", std::vector<double>(feed_->force.data(), feed_->force.data() + feed_->force.size())},
                   {"about", std::vector<double>(feed_->about.data(), feed_->about.data() + feed_->about.size())},
                   {"t", t_}};
  return j.dump();
}

void ExportedModel::RestoreState(const std::string& bytes) {
  if (!initialized_) throw Error("the FMU state can be set after initialization only");
  const nlohmann::json j = nlohmann::json::parse(bytes);
  const auto values = j.at("values").get<std::vector<double>>();
  if (values.size() != values_.size()) throw Error("the FMU state is of another model");
  // The parameters in effect travel with the state (issue 48): the session is rebuilt with
  // every parameter of the state written into the config (its start value gives the start run
  // bit for bit, so writing all of them is exact).
  for (std::size_t vr = 0; vr < layout_.variables.size(); ++vr) {
    const Variable& v = layout_.variables[vr];
    if (v.kind == Variable::Kind::kParameter) {
      values_[vr] = values[vr];
      parameter_set_[v.index] = true;
    }
  }
  spec_.emplace(Compile());
  const auto force = j.at("force").get<std::vector<double>>();
  const auto about = j.at("about").get<std::vector<double>>();
  for (std::size_t k = 0; k < force.size(); ++k) {
    feed_->force(static_cast<long>(k)) = force[k];
    feed_->about(static_cast<long>(k)) = about[k];
  }
  auto session = NewSession();
  session->SetState(runner::RunStateFromJson(j.at("run_state"), "the FMU state"));
  Check(session->Initialize(), "restoring the FMU state");
  session_ = std::move(session);
  values_ = values;
  t_ = j.at("t").get<double>();
}

}  // namespace hybridtest::fmu_export
