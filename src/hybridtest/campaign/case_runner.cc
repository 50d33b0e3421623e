// See case_runner.h.
#include "hybridtest/campaign/case_runner.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/plan.h"
#include "hybridtest/runner/pre_move_checks.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::campaign {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The campaign's journal metrics, accumulated over the journal's rows as they are committed.
class MetricObserver final : public runner::SessionObserver {
 public:
  MetricObserver(const std::vector<MetricSpec>& metrics, const io::RunSpec& spec)
      : metrics_(metrics), acc_(metrics.size()) {
    const auto channels = runner::JournalChannels(spec);
    for (std::size_t m = 0; m < metrics.size(); ++m) {
      for (std::size_t c = 0; c < channels.size(); ++c) {
        if (channels[c].name == metrics[m].channel) acc_[m].column = static_cast<int>(c);
      }
      if (acc_[m].column < 0 && metrics[m].kind != MetricSpec::kError) {
        std::string names;
        for (const auto& ch : channels) names += (names.empty() ? "" : ", ") + ch.name;
        throw ConfigError(fmt::format("metric {}: the journal has no channel '{}'; its channels "
                                      "are {}", metrics[m].name, metrics[m].channel, names));
      }
    }
  }
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kUncommitted) return;
    for (auto& a : acc_) {
      if (a.column < 0) continue;
      const double v = e.row[static_cast<std::size_t>(a.column)];
      a.max_abs = std::max(a.max_abs, std::abs(v));
      a.max = std::max(a.max, v);
      a.min = std::min(a.min, v);
      a.sum_sq += v * v;
      a.final = v;
      ++a.count;
    }
  }
  std::vector<double> Values() const {
    std::vector<double> out;
    for (std::size_t m = 0; m < metrics_.size(); ++m) {
      const Acc& a = acc_[m];
      double v = kNaN;
      if (a.count > 0) {
        switch (metrics_[m].kind) {
          case MetricSpec::kMaxAbs: v = a.max_abs; break;
          case MetricSpec::kMax: v = a.max; break;
          case MetricSpec::kMin: v = a.min; break;
          case MetricSpec::kRms: v = std::sqrt(a.sum_sq / static_cast<double>(a.count)); break;
          case MetricSpec::kFinal: v = a.final; break;
          case MetricSpec::kError: break;
        }
      }
      out.push_back(v);
    }
    return out;
  }

 private:
  struct Acc {
    int column = -1;
    double max_abs = 0.0, max = -std::numeric_limits<double>::infinity(),
           min = std::numeric_limits<double>::infinity(), sum_sq = 0.0, final = kNaN;
    long count = 0;
  };
  const std::vector<MetricSpec>& metrics_;
  std::vector<Acc> acc_;
};

// Files of an attempt that never wrote its case.json go to interrupted-N/ (never destroyed).
void MoveAsideUnfinished(const fs::path& dir) {
  std::vector<fs::path> leftovers;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name == "config.yaml" || name.rfind("interrupted-", 0) == 0) continue;
    leftovers.push_back(entry.path());
  }
  if (leftovers.empty()) return;
  int n = 1;
  while (fs::exists(dir / fmt::format("interrupted-{}", n))) ++n;
  const fs::path aside = dir / fmt::format("interrupted-{}", n);
  fs::create_directory(aside);
  for (const auto& p : leftovers) fs::rename(p, aside / p.filename());
  io::SyncDirectory(dir.string());
}

void RunSimulation(const Campaign& campaign, const io::SimulationConfig& cfg,
                   const std::string& csv, const CaseHooks& hooks, CaseResult& result) {
  const bool run = campaign.command == CaseCommand::kRun;
  io::RunSpec spec = io::CompileRunSpec(
      cfg, {std::nullopt, run, "`simulate` is numerical only: use `command: run` for a hybrid "
                               "test", std::nullopt});
  for (const auto& sub : spec.substructures) {
    std::string type = sub.physical ? sub.physical->transfer.type : "";
    // A delay compensator around a bench is that bench ("compensated rt_plant").
    while (type.rfind("compensated ", 0) == 0) type.erase(0, std::string("compensated ").size());
    if (sub.is_physical() && type != "emulated" && type != "loopback" && type != "rt_plant") {
      throw ConfigError(fmt::format(
          "slot {}: a campaign runs cases on in-process benches only (emulated, loopback, "
          "rt_plant, compensated); a real bench is run one test at a time with `hybridtest run`",
          sub.slot));
    }
  }
  // A real-time case is paced by the Session on the virtual clock: cases run one after the
  // other (or side by side under MPI) and none may take the machine's clock from another.
  if (spec.real_time.enabled) {
    if (spec.real_time.clock == "wall") {
      throw ConfigError(
          "real_time.clock: wall: a campaign runs its real-time cases in virtual time (cases "
          "share the machine, and a wall-clock loop needs it alone); remove `clock: wall` (or "
          "set `clock: virtual`), or run the case on its own with `hybridtest run CONFIG`");
    }
    spec.real_time.clock = "virtual";
  }
  spec.output.csv_path = csv;
  spec.output.command = CaseCommandName(campaign.command);
  spec.quiet = true;
  // The front door, as `run`'s: lock, output guards, disk budget, input record, provenance.
  runner::OpenedRun opened = runner::OpenRun(
      spec, {.command_line = hooks.command_line, .provenance = hooks.provenance});
  runner::Session session(std::move(spec), std::move(opened));
  MetricObserver metrics(campaign.metrics, session.spec());
  session.AddObserver(metrics);
  const runner::StepResult r = session.Run();
  result.metrics = metrics.Values();
  if (r.status != runner::SessionStatus::kFinished) {
    result.status = "failed";
    result.error = fmt::format("{}: {}", runner::StatusName(r.status), r.reason);
  }
}

void RunPlan(const Campaign& campaign, const io::SimulationConfig& cfg, CaseResult& result) {
  io::SubstructureOptions options;
  if (!campaign.plan_emulate.empty()) options.emulate_bench = campaign.plan_emulate;
  const io::RunSpec spec = io::CompileRunSpec(cfg, options);
  runner::CheckSchemeStability(spec);  // refused as its run would be
  runner::PlanOptions plan;
  plan.tolerance = campaign.plan_tolerance;
  if (!campaign.plan_emulate.empty()) plan.emulate_bench = campaign.plan_emulate;
  const auto results = runner::PlanTest(spec, plan);
  nlohmann::json candidates = nlohmann::json::array();
  for (const auto& c : results) {
    candidates.push_back({{"scheme", c.candidate.label}, {"ok", c.ok}, {"failure", c.failure},
                          {"evaluations", c.evaluations}, {"lab_time", c.lab_time},
                          {"error", c.error}, {"reversals", c.reversals}});
  }
  result.plan["candidates"] = candidates;
  const auto best = runner::Recommend(results, campaign.plan_tolerance);
  result.plan["recommendation"] = best ? best->candidate.label : std::string("none");
  result.plan["evaluations"] = best ? best->evaluations : 0L;
  result.plan["error"] = best ? best->error : kNaN;
  result.plan["lab_time"] = best ? best->lab_time : kNaN;
  if (best) result.plan["integrator"] = runner::IntegratorYaml(best->candidate);
  result.metrics.assign(campaign.metrics.size(), kNaN);
}

double JsonNumber(const nlohmann::json& j) { return j.is_number() ? j.get<double>() : kNaN; }

}  // namespace

nlohmann::json ToJson(const CaseResult& r) {
  nlohmann::json metrics = nlohmann::json::array();
  for (double v : r.metrics) metrics.push_back(std::isfinite(v) ? nlohmann::json(v) : nullptr);
  return {{"index", r.index}, {"id", r.id}, {"status", r.status}, {"error", r.error},
          {"duration", r.duration}, {"metrics", metrics}, {"plan", r.plan},
          {"worker", r.worker}};
}

CaseResult CaseResultFromJson(const nlohmann::json& j) {
  CaseResult r;
  r.index = j.at("index").get<int>();
  r.id = j.at("id").get<std::string>();
  r.status = j.at("status").get<std::string>();
  r.error = j.value("error", "");
  r.duration = j.value("duration", 0.0);
  for (const auto& v : j.at("metrics")) r.metrics.push_back(JsonNumber(v));
  r.plan = j.value("plan", nlohmann::json::object());
  r.worker = j.value("worker", "");
  return r;
}

std::string CaseDir(const std::string& out_dir, const Campaign& campaign, int index) {
  return (fs::path(out_dir) / "cases" / campaign.cases.at(index).id).string();
}

std::string CaseJournal(const std::string& out_dir, const Campaign& campaign, int index) {
  return (fs::path(CaseDir(out_dir, campaign, index)) / "run.csv").string();
}

std::optional<CaseResult> ReadCaseResult(const std::string& out_dir, const Campaign& campaign,
                                         int index) {
  const fs::path path = fs::path(CaseDir(out_dir, campaign, index)) / "case.json";
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    nlohmann::json j = nlohmann::json::parse(in);
    CaseResult r = CaseResultFromJson(j);
    if (r.id != campaign.cases.at(index).id) return std::nullopt;
    r.metrics.resize(campaign.metrics.size(), kNaN);
    return r;
  } catch (const std::exception&) {
    return std::nullopt;  // a torn or foreign file: the case runs again
  }
}

CaseResult RunCase(const Campaign& campaign, int index, const std::string& out_dir,
                   const CaseHooks& hooks, const std::string& worker) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult result;
  result.index = index;
  result.id = campaign.cases.at(index).id;
  result.status = "finished";
  result.worker = worker;
  result.metrics.assign(campaign.metrics.size(), kNaN);
  const std::string dir = CaseDir(out_dir, campaign, index);
  try {
    fs::create_directories(dir);
    MoveAsideUnfinished(dir);
    const std::string config = (fs::path(dir) / "config.yaml").string();
    io::WriteFileAtomically(config, CaseConfigText(campaign, index, dir));
    const io::SimulationConfig cfg = io::LoadSimulationConfig(config);
    if (campaign.command == CaseCommand::kPlan) {
      RunPlan(campaign, cfg, result);
    } else {
      RunSimulation(campaign, cfg, CaseJournal(out_dir, campaign, index), hooks, result);
    }
  } catch (const std::exception& e) {
    result.status = "failed";
    result.error = e.what();
  }
  result.duration =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  try {
    io::WriteFileAtomically((fs::path(dir) / "case.json").string(), ToJson(result).dump(2) + "\n");
  } catch (const std::exception& e) {
    result.status = "failed";
    result.error += fmt::format("{}the case's record could not be written: {}",
                                result.error.empty() ? "" : "; ", e.what());
  }
  return result;
}

}  // namespace hybridtest::campaign
