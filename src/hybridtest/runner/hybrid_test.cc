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
#include "hybridtest/io/journal.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/substructures/physical_substructure.h"
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
// What the schemes may know of the substructures: K0 and the largest safe increment per slot.
schemes::SlotInfo SlotInfoOf(const SubstructureList& subs) {
  schemes::SlotInfo info{Eigen::VectorXd::Zero(static_cast<Eigen::Index>(subs.size())),
                         Eigen::VectorXd::Zero(static_cast<Eigen::Index>(subs.size()))};
  for (std::size_t s = 0; s < subs.size(); ++s) {
    info.k0(static_cast<Eigen::Index>(s)) =
        subs[s]->initial_stiffness().value_or(std::numeric_limits<double>::quiet_NaN());
    info.max_increment(static_cast<Eigen::Index>(s)) = subs[s]->max_displacement_increment();
  }
  return info;
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

void HybridTest::MeasureRequestedStiffness() {
  stiffness_record_ = nlohmann::json::array();
  const multibody::Model& model = cfg_.model.model;
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    nlohmann::json entry = {{"slot", model.slots()[s].info.name}};
    auto* physical = dynamic_cast<substructures::PhysicalSubstructure*>(subs_[s].get());
    if (physical != nullptr && physical->requested_stiffness_ramp()) {
      const auto m = physical->MeasureInitialStiffness(*physical->requested_stiffness_ramp());
      nlohmann::json samples = nlohmann::json::array();
      for (const auto& [d, r] : m.samples) samples.push_back({d, r});
      entry.update({{"k0", m.k0}, {"source", "measured"}, {"amplitude_m", m.amplitude},
                    {"samples_d_m_r_N", samples}});
    } else if (const auto k0 = subs_[s]->initial_stiffness()) {
      entry.update({{"k0", *k0}, {"source", subs_[s]->is_physical() ? "configured" : "law"}});
    } else {
      entry.update({{"k0", nullptr}, {"source", "unknown"}});
    }
    stiffness_record_.push_back(entry);
  }
}

RunStatistics HybridTest::Run() {
  const multibody::Model& model = cfg_.model.model;
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  bool physical = false;
  for (const auto& s : subs_) physical = physical || s->is_physical();

  // Records first: a run that cannot write its journal must not move anything.
  const auto channels = JournalChannels(cfg_, subs_);
  const io::SyncPolicy policy = physical ? io::SyncPolicy::kEveryRow : io::SyncPolicy::kBuffered;
  const RunState* resume = options_.resume_from;
  std::optional<io::Journal> journal_storage;
  if (resume != nullptr) {
    rows_cut_ = CutJournalToRows(options_.csv_path, resume->rows);
    journal_storage.emplace(io::kReopenForAppend, options_.csv_path, policy);
  } else {
    io::JournalMetadata metadata = JournalMetadataFor(cfg_, subs_, options_.command);
    metadata.extra["inputs"] = options_.inputs;
    journal_storage.emplace(options_.csv_path, channels, std::move(metadata), policy);
  }
  io::Journal& journal = *journal_storage;
  std::optional<io::Journal> stages;
  if (physical && options_.record_stages) {
    // Flushed to the kernel every row (a killed process loses nothing); synced to the disk
    // in batches: the journal itself is synced every row.
    if (resume != nullptr && std::filesystem::exists(io::StagesPath(options_.csv_path))) {
      stages.emplace(io::kReopenForAppend, io::StagesPath(options_.csv_path),
                     io::SyncPolicy::kBatched, 100);
    } else {
      stages.emplace(io::StagesPath(options_.csv_path), StageChannels(cfg_, subs_),
                     JournalMetadataFor(cfg_, subs_, options_.command), io::SyncPolicy::kBatched,
                     100);
    }
  }
  const std::string state_path = RunStatePath(options_.csv_path);
  long state_rows = 0;  // rows of the last saved state

  multibody::Data<double> data(model);
  Eigen::VectorXd d(m), r0(m);
  Eigen::VectorXd row(static_cast<Eigen::Index>(channels.size()));
  Eigen::VectorXd stage_values(stages ? static_cast<Eigen::Index>(stages->channels().size()) : 0);
  Progress progress(options_.progress);
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall = [&] {
    return wall_offset_ +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
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
  // Journal row of a committed state xs with restoring forces rs; `measured`: the physical
  // channels hold the last exchange (else NaN: no specimen sample belongs to this row).
  auto fill_row = [&](double t, const Eigen::VectorXd& xs, const Eigen::VectorXd& rs,
                      bool measured) {
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
  };
  // Appends `row` as it is.
  auto append_row = [&](bool measured) {
    journal.Append(std::span<const double>(row.data(), row.size()), measured);
    stats_.rows = journal.rows();
  };
  auto write_row = [&](double t, const Eigen::VectorXd& xs, const Eigen::VectorXd& rs,
                       bool measured) {
    fill_row(t, xs, rs, measured);
    append_row(measured);
  };

  // The seam: trials of every substructure at a state (and the stage record).
  auto stage_row = [&](long step, int stage, double t) {
    if (!stages) return;
    Eigen::Index c = 0;
    stage_values(c++) = static_cast<double>(step);
    stage_values(c++) = stage;
    stage_values(c++) = t;
    for (const auto& s : subs_) {
      if (!s->is_physical()) continue;
      const auto e = s->last_exchange();
      for (double v : {e.command, e.position, e.force, e.lab_time,
                       static_cast<double>(e.force_reversals)}) {
        stage_values(c++) = v;
      }
    }
    stages->Append(std::span<const double>(stage_values.data(), stage_values.size()));
  };
  schemes::SeamOf seam([&](long step, int stage, double t, const Eigen::VectorXd& xs,
                           Eigen::Ref<Eigen::VectorXd> r) {
    multibody::CalcSlotDisplacements<double>(model, data, t, xs.head(n), d);
    for (int s = 0; s < m; ++s) r(s) = subs_[s]->Trial(d(s), {step, stage, t});
    stage_row(step, stage, t);
  });
  // A scheme's intermediate rows (no specimen sample belongs to them).
  schemes::RowSinkOf rows([&](double t, const Eigen::VectorXd& xs, const Eigen::VectorXd& rs) {
    write_row(t, xs, rs, false);
  });

  std::unique_ptr<schemes::HybridScheme> scheme;
  double t_now = 0.0;
  // The run state goes to disk before its committed row (resume writes a lost row from it):
  // at every commit with a physical slot, else at the journal's batch syncs and at the end.
  // `row` holds the committed row's values.
  auto save_state = [&](bool always, long rows_after) {
    if (!options_.save_state) return;
    if (!always && !physical && rows_after / 1000 == state_rows / 1000) return;
    journal.Flush();  // its rows before the state's are in the kernel (kBuffered holds some)
    RunState state = CaptureState(*scheme, rows_after, stages ? stages->rows() : 0,
                                  ToJson(stats_));
    state.row.assign(row.data(), row.data() + row.size());
    state.journal_rows = journal.rows();
    if (journal.rows() > 0) state.journal_last_row = journal.last_row();
    SaveRunState(state_path, state);
    state_rows = rows_after;
  };
  try {
    for (auto& s : subs_) s->Activate();
    if (resume != nullptr) {
      RestoreSubstructures(*resume);
      scheme = schemes::MakeScheme(cfg_.scheme, cfg_.tableau, cfg_.dt, cfg_.duration, cfg_.steps,
                                   model, SlotInfoOf(subs_));
      ResumeFrom(*resume, *scheme, journal, [&] {
        const schemes::CommittedPoint& p = scheme->committed();
        write_row(p.t, p.x, p.r, true);
      }, stage_row);
      state_rows = resume->rows;
      t_now = scheme->committed().t;
    } else {
      MeasureRequestedStiffness();
      scheme = schemes::MakeScheme(cfg_.scheme, cfg_.tableau, cfg_.dt, cfg_.duration, cfg_.steps,
                                   model, SlotInfoOf(subs_));
      // The initial state: tried (stage 0 of step 0), committed, journalled.
      seam.Trial(0, 0, 0.0, cfg_.x0, r0);
      for (auto& s : subs_) s->Commit();
      scheme->Start(0.0, cfg_.x0, r0);
      // Row 0 first: it publishes the journal; the state of a run that never published stays
      // that of the earlier run at the same path.
      write_row(0.0, cfg_.x0, r0, true);
      save_state(true, journal.rows());  // `row` still holds row 0
    }
    while (!scheme->finished()) {
      scheme->Step(seam, rows);
      const schemes::CommittedPoint& p = scheme->committed();
      for (auto& s : subs_) s->Commit();
      stats_.steps = p.step;
      fill_row(p.t, p.x, p.r, true);
      save_state(scheme->finished(), journal.rows() + 1);
      append_row(true);
      t_now = p.t;
      update_stats(p.t);
      progress.Update({p.step, p.step + scheme->EstimatedStepsLeft(cfg_.duration), p.t,
                       cfg_.duration, stats_.physical_evaluations, stats_.lab_time,
                       stats_.wall_time});
      if (StopRequested() && !scheme->finished()) {
        throw Interrupted(fmt::format("interrupted by the operator at t = {} s after {} steps; "
                                      "every committed step is in {}", p.t, p.step,
                                      options_.csv_path));
      }
    }
    for (auto& s : subs_) s->Deactivate();
  } catch (const std::exception& e) {
    for (auto& s : subs_) s->Hold();
    // A state computed but not committed (its own trial failed) is recorded without forces.
    if (scheme && scheme->uncommitted() != nullptr) {
      try {
        const schemes::CommittedPoint& u = *scheme->uncommitted();
        stats_.steps = u.step;  // the step that computed it is done; its trial failed
        t_now = u.t;
        write_row(u.t, u.x, Eigen::VectorXd::Constant(m, std::numeric_limits<double>::quiet_NaN()),
                  false);
      } catch (const std::exception&) {
        // The journal itself failed; the original error is the one to report.
      }
    }
    // Nothing committed (the run could not start): no row, so the journal is never published
    // and an earlier run at this path survives (decision 0008).
    update_stats(t_now);
    progress.Finish();
    nlohmann::json statistics = ToJson(stats_);
    statistics["initial_stiffness"] = stiffness_record_;
    statistics["stop"] = StopDetails(e);
    // How many commands each in-process bench had received: a resume tells it, so that a
    // test fault that stopped the run does not fire again.
    nlohmann::json received = nlohmann::json::array();
    for (const auto& s : subs_) {
      const auto* p = dynamic_cast<const substructures::PhysicalSubstructure*>(s.get());
      const auto count = p != nullptr ? p->transfer().commands_received() : std::nullopt;
      received.push_back(count ? nlohmann::json(*count) : nlohmann::json(nullptr));
    }
    statistics["stop"]["commands_received"] = received;
    try {
      journal.Finish(statistics, std::string("stopped: ") + e.what());
      if (stages) stages->Finish(statistics, std::string("stopped: ") + e.what());
    } catch (const std::exception&) {
    }
    throw;
  }
  update_stats(t_now);
  progress.Finish();
  nlohmann::json statistics = ToJson(stats_);
  statistics["initial_stiffness"] = stiffness_record_;
  journal.Finish(statistics, "completed");
  if (stages) stages->Finish(statistics, "completed");
  return stats_;
}

}  // namespace hybridtest::runner
