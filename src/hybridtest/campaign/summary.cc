// See summary.h.
#include "hybridtest/campaign/summary.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "hybridtest/io/csv.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"
#include "hybridtest/report/plot_figure.h"

namespace hybridtest::campaign {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out(1, '"');
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out.push_back('"');
  return out;
}

std::string Number(double v) {
  if (!std::isfinite(v)) return "";
  std::string out;
  io::AppendCsvNumber(v, out);
  return out;
}

std::string PlanField(const CaseResult& r, const char* key) {
  const auto it = r.plan.find(key);
  if (it == r.plan.end() || it->is_null()) return "";
  if (it->is_number()) return Number(it->get<double>());
  return Field(it->is_string() ? it->get<std::string>() : it->dump());
}

}  // namespace

void FillErrorMetrics(const Campaign& campaign, const std::string& out_dir,
                      std::vector<std::optional<CaseResult>>& results) {
  bool any = false;
  for (const auto& m : campaign.metrics) any = any || m.kind == MetricSpec::kError;
  if (!any || campaign.reference < 0 || campaign.command == CaseCommand::kPlan) return;
  const auto& ref_result = results.at(campaign.reference);
  if (!ref_result || ref_result->status != "finished") return;
  io::RunData reference;
  try {
    reference = io::LoadRun(CaseJournal(out_dir, campaign, campaign.reference));
  } catch (const std::exception&) {
    return;
  }
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (!results[i] || results[i]->status != "finished") continue;
    io::RunData run;
    try {
      run = io::LoadRun(CaseJournal(out_dir, campaign, static_cast<int>(i)));
    } catch (const std::exception&) {
      continue;
    }
    for (std::size_t m = 0; m < campaign.metrics.size(); ++m) {
      const MetricSpec& spec = campaign.metrics[m];
      if (spec.kind != MetricSpec::kError) continue;
      double value = kNaN;
      if (run.Has(spec.channel) && reference.Has(spec.channel) && run.Has("t") &&
          run.num_rows() == reference.num_rows() &&
          (run.Get("t") - reference.Get("t")).cwiseAbs().maxCoeff() <= 1e-9) {
        value = (run.Get(spec.channel) - reference.Get(spec.channel)).cwiseAbs().maxCoeff();
      }
      results[i]->metrics.resize(campaign.metrics.size(), kNaN);
      results[i]->metrics[m] = value;
    }
  }
}

std::string SummaryCsv(const Campaign& campaign,
                       const std::vector<std::optional<CaseResult>>& results) {
  const bool plan = campaign.command == CaseCommand::kPlan;
  std::string out = "case";
  // A comma, then the field (not `"," + field`: GCC 12 warns -Wrestrict there).
  const auto add = [&out](const std::string& field) {
    out.push_back(',');
    out += field;
  };
  for (const auto& key : campaign.varied) add(Field(key));
  out += ",status,duration_s,worker";
  for (const auto& m : campaign.metrics) add(Field(m.name));
  if (plan) out += ",recommendation,evaluations,plan_error,lab_time_s";
  out += ",error\n";
  for (std::size_t i = 0; i < campaign.cases.size(); ++i) {
    const CaseSpec& c = campaign.cases[i];
    out += Field(c.id);
    for (const auto& [key, value] : c.params) add(Field(value));
    const std::optional<CaseResult>& r = results.at(i);
    if (!r) {
      out += ",pending,,";
      out += std::string(campaign.metrics.size(), ',');
      if (plan) out += ",,,,";
      out += ",\n";
      continue;
    }
    out += fmt::format(",{},{},{}", r->status, Number(r->duration), Field(r->worker));
    for (std::size_t m = 0; m < campaign.metrics.size(); ++m) {
      add(Number(m < r->metrics.size() ? r->metrics[m] : kNaN));
    }
    if (plan) {
      for (const char* key : {"recommendation", "evaluations", "error", "lab_time"}) {
        add(PlanField(*r, key));
      }
    }
    add(Field(r->error));
    out.push_back('\n');
  }
  return out;
}

std::vector<std::string> WriteCampaignFigures(
    const Campaign& campaign, const std::vector<std::optional<CaseResult>>& results,
    const std::string& out_dir) {
  // (name, value of case i) for every numeric quantity of the summary.
  // (name with its unit, value of case i) for every numeric quantity of the summary; the
  // units from the first finished case's journal.
  std::optional<io::RunData> run;
  for (std::size_t i = 0; i < results.size() && !run; ++i) {
    if (!results[i] || results[i]->status != "finished") continue;
    try {
      if (campaign.command != CaseCommand::kPlan) {
        run = io::LoadRun(CaseJournal(out_dir, campaign, static_cast<int>(i)));
      }
    } catch (const std::exception&) {
    }
  }
  std::vector<std::pair<std::string, std::vector<double>>> quantities;
  for (std::size_t m = 0; m < campaign.metrics.size(); ++m) {
    std::vector<double> v;
    for (const auto& r : results) {
      v.push_back(r && r->status == "finished" && m < r->metrics.size() ? r->metrics[m] : kNaN);
    }
    const std::string& channel = campaign.metrics[m].channel;
    const std::string unit = run && run->Has(channel) ? run->Unit(channel) : "";
    quantities.emplace_back(campaign.metrics[m].name + (unit.empty() ? "" : " [" + unit + "]"),
                            v);
  }
  if (campaign.command == CaseCommand::kPlan) {
    for (const char* key : {"evaluations", "error", "lab_time"}) {
      std::vector<double> v;
      for (const auto& r : results) {
        const bool ok = r && r->plan.contains(key) && r->plan[key].is_number();
        v.push_back(ok ? r->plan[key].get<double>() : kNaN);
      }
      quantities.emplace_back(std::string("plan ") + key, v);
    }
  }
  std::vector<report::PlotFigure> figures;
  for (std::size_t p = 0; p < campaign.varied.size(); ++p) {
    std::vector<double> x;
    bool numeric = true;
    for (const auto& c : campaign.cases) {
      const auto v = io::ParseCsvNumber(c.params.at(p).second);
      numeric = numeric && v.has_value();
      x.push_back(v ? *v : kNaN);
    }
    if (!numeric) continue;
    for (const auto& [name, y] : quantities) {
      // One line per combination of the other varied values.
      std::map<std::string, std::vector<std::pair<double, double>>> lines;
      for (std::size_t i = 0; i < campaign.cases.size(); ++i) {
        if (!std::isfinite(y[i])) continue;
        std::string label;
        for (std::size_t q = 0; q < campaign.varied.size(); ++q) {
          if (q == p) continue;
          const auto parts = SplitKeyPath(campaign.varied[q]);
          label += fmt::format("{}{} = {}", label.empty() ? "" : ", ", parts.back(),
                               campaign.cases[i].params[q].second);
        }
        lines[label].emplace_back(x[i], y[i]);
      }
      if (lines.empty()) continue;
      report::PlotPanel panel;
      panel.x_is_time = false;
      panel.x_label = campaign.varied[p];
      panel.y_label = name;
      std::size_t color = 0;
      for (auto& [label, points] : lines) {
        std::sort(points.begin(), points.end());
        report::PlotSeries s;
        s.label = label.empty() ? name : label;
        s.x.resize(static_cast<Eigen::Index>(points.size()));
        s.y.resize(static_cast<Eigen::Index>(points.size()));
        for (std::size_t k = 0; k < points.size(); ++k) {
          s.x[static_cast<Eigen::Index>(k)] = points[k].first;
          s.y[static_cast<Eigen::Index>(k)] = points[k].second;
        }
        const auto& palette = report::NonPhysicalPalette();
        s.color = palette[color++ % palette.size()];
        panel.series.push_back(std::move(s));
      }
      std::string stem;
      for (char ch : name.substr(0, name.find(" [")) + "-vs-" +
                         SplitKeyPath(campaign.varied[p]).back()) {
        if (ch == ')') continue;
        stem += std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.' ? ch
                : ch == '(' ? '-' : '_';
      }
      figures.push_back(
          {stem, fmt::format("{} against {}", name, campaign.varied[p]), {panel}});
    }
  }
  if (figures.empty()) return {};
  report::GnuplotOptions options;
  options.script.svg = false;
  return report::RenderFigures(figures, (fs::path(out_dir) / "figures").string(), options);
}

}  // namespace hybridtest::campaign
