// See hybrid_test.h.
#include "hybridtest/runner/hybrid_test.h"

#include "hybridtest/runner/stop_request.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::runner {

namespace {
nlohmann::json ToJson(const RunStatistics& s) {
  return {{"steps", s.steps},           {"rows", s.rows},
          {"physical_evaluations", s.physical_evaluations},
          {"sim_time_s", s.sim_time},   {"wall_time_s", s.wall_time},
          {"lab_time_s", s.lab_time},   {"slowdown", s.slowdown},
          {"wall_slowdown", s.wall_slowdown}};
}

nlohmann::json StopDetails(const std::exception& e) {
  nlohmann::json stop = {{"message", e.what()}};
  if (const auto* safety = dynamic_cast<const transfer::SafetyStop*>(&e)) {
    stop["kind"] = "safety";
    stop["limit"] = safety->limit();
    stop["value"] = safety->value();
    stop["limit_value"] = safety->limit_value();
    stop["step"] = safety->step();
    stop["stage"] = safety->stage();
    nlohmann::json history = nlohmann::json::array();
    for (const auto& h : safety->history()) {
      history.push_back({{"step", h.step}, {"stage", h.stage}, {"command", h.command},
                         {"position", h.position}, {"force", h.force}, {"answered", h.answered}});
    }
    stop["history"] = history;
  } else if (dynamic_cast<const TransferError*>(&e) != nullptr) {
    stop["kind"] = "transfer";
  } else if (dynamic_cast<const Interrupted*>(&e) != nullptr) {
    stop["kind"] = "interrupted";
  } else {
    stop["kind"] = "error";
  }
  return stop;
}
}  // namespace

std::string ResolveOutputPath(const io::SimulationConfig& cfg, const std::string& out_option) {
  if (!out_option.empty()) return out_option;
  if (!cfg.output_csv.empty()) return cfg.output_csv;
  return "results/" + std::filesystem::path(cfg.input.path()).stem().string() + ".csv";
}

HybridTest::HybridTest(const io::SimulationConfig& cfg, SubstructureList substructures,
                       RunOptions options)
    : cfg_(cfg), subs_(std::move(substructures)), options_(std::move(options)) {
  if (static_cast<int>(subs_.size()) != cfg_.model.model.num_slots()) {
    throw Error(fmt::format("HybridTest: {} substructures for {} slots", subs_.size(),
                            cfg_.model.model.num_slots()));
  }
}

RunStatistics HybridTest::Run() {
  const multibody::Model& model = cfg_.model.model;
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  const double h = cfg_.dt;
  bool physical = false;
  for (const auto& s : subs_) physical = physical || s->is_physical();

  // Records first: a run that cannot write its journal must not move anything.
  const auto channels = JournalChannels(cfg_, subs_);
  io::Journal journal(options_.csv_path, channels, JournalMetadataFor(cfg_, subs_, options_.command),
                      physical ? io::SyncPolicy::kEveryRow : io::SyncPolicy::kBatched);
  std::optional<io::Journal> stages;
  if (physical && options_.record_stages) {
    const std::filesystem::path p(options_.csv_path);
    stages.emplace((p.parent_path() / (p.stem().string() + ".stages.csv")).string(),
                   StageChannels(cfg_, subs_), JournalMetadataFor(cfg_, subs_, options_.command),
                   // Flushed to the kernel every row (a killed process loses nothing); synced
                   // to the disk in batches: the journal itself is synced every row.
                   io::SyncPolicy::kBatched, 100);
  }

  multibody::Data<double> data(model);
  integrators::ExplicitRungeKutta stepper(cfg_.tableau, 2 * n);
  Eigen::VectorXd x = cfg_.x0, x_next(2 * n), d(m), r(m);
  Eigen::VectorXd row(static_cast<Eigen::Index>(channels.size()));
  Eigen::VectorXd stage_row(stages ? static_cast<Eigen::Index>(stages->channels().size()) : 0);
  Progress progress(options_.progress);
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  auto update_stats = [&](double t) {
    stats_.sim_time = t;
    stats_.wall_time = wall();
    stats_.physical_evaluations = 0;
    for (const auto& s : subs_) {
      stats_.physical_evaluations += s->evaluations();
      if (s->is_physical()) stats_.lab_time = std::max(stats_.lab_time, s->last_exchange().lab_time);
    }
    stats_.slowdown = t > 0.0 && physical ? stats_.lab_time / t : 0.0;
    stats_.wall_slowdown = t > 0.0 ? stats_.wall_time / t : 0.0;
  };
  // Trials of every substructure at state xs (stage `stage` of step `step`) → r.
  auto trial_all = [&](long step, int stage, double t, const Eigen::VectorXd& xs) {
    multibody::CalcSlotDisplacements<double>(model, data, t, xs.head(n), d);
    for (int s = 0; s < m; ++s) r(s) = subs_[s]->Trial(d(s), {step, stage, t});
    if (!stages) return;
    Eigen::Index c = 0;
    stage_row(c++) = static_cast<double>(step);
    stage_row(c++) = stage;
    stage_row(c++) = t;
    for (const auto& s : subs_) {
      if (!s->is_physical()) continue;
      const auto e = s->last_exchange();
      for (double v : {e.command, e.position, e.force, e.lab_time}) stage_row(c++) = v;
    }
    stages->Append(std::span<const double>(stage_row.data(), stage_row.size()));
  };
  // Journal row of the committed state xs with restoring forces rs.
  auto write_row = [&](double t, const Eigen::VectorXd& xs, const Eigen::VectorXd& rs, bool measured) {
    Eigen::Index c = 0;
    row(c++) = t;
    row.segment(c, 2 * n) = xs;
    c += 2 * n;
    row.segment(c, m) = rs;
    c += m;
    for (const auto& s : subs_) {
      if (!s->is_physical()) continue;
      const auto e = s->last_exchange();
      for (double v : {e.command, e.position, e.force, e.lab_time}) {
        row(c++) = measured ? v : std::numeric_limits<double>::quiet_NaN();
      }
    }
    journal.Append(std::span<const double>(row.data(), row.size()));
    stats_.rows = journal.rows();
  };

  long step = 0;
  try {
    for (auto& s : subs_) s->Activate();
    for (; step < cfg_.steps; ++step) {
      const double t = static_cast<double>(step) * h;
      stepper.Step(t, h, x,
                   [&](int i, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                     trial_all(step, i, t_i, x_i);
                     if (i == 0) {
                       for (auto& s : subs_) s->Commit();
                       write_row(t, x, r, true);
                     }
                     multibody::CalcStateDerivative<double>(model, data, t_i, x_i, r, k);
                   },
                   x_next);
      x.swap(x_next);
      stats_.steps = step + 1;
      update_stats(static_cast<double>(step + 1) * h);
      progress.Update({step + 1, cfg_.steps, stats_.sim_time, cfg_.duration,
                       stats_.physical_evaluations, stats_.lab_time, stats_.wall_time});
      if (StopRequested()) {
        ++step;  // x is the committed state of the next step, not yet journalled
        throw Interrupted(fmt::format("interrupted by the operator at t = {} s after {} steps; "
                                      "every committed step is in {}", stats_.sim_time, step,
                                      options_.csv_path));
      }
    }
    // The last committed state gets its row too.
    const double t_end = static_cast<double>(cfg_.steps) * h;
    trial_all(cfg_.steps, 0, t_end, x);
    for (auto& s : subs_) s->Commit();
    write_row(t_end, x, r, true);
    for (auto& s : subs_) s->Deactivate();
  } catch (const std::exception& e) {
    for (auto& s : subs_) s->Hold();
    // x is the committed state x_step; its row exists unless its own trial failed.
    if (journal.rows() == step) {
      try {
        write_row(static_cast<double>(step) * h, x,
                  Eigen::VectorXd::Constant(m, std::numeric_limits<double>::quiet_NaN()), false);
      } catch (const std::exception&) {
        // The journal itself failed; the original error is the one to report.
      }
    }
    update_stats(static_cast<double>(step) * h);
    progress.Finish();
    nlohmann::json statistics = ToJson(stats_);
    statistics["stop"] = StopDetails(e);
    try {
      journal.Finish(statistics, std::string("stopped: ") + e.what());
      if (stages) stages->Finish(statistics, std::string("stopped: ") + e.what());
    } catch (const std::exception&) {
    }
    throw;
  }
  update_stats(static_cast<double>(cfg_.steps) * h);
  progress.Finish();
  journal.Finish(ToJson(stats_), "completed");
  if (stages) stages->Finish(ToJson(stats_), "completed");
  return stats_;
}

}  // namespace hybridtest::runner
