#include "hybridtest/report/html_report_summary.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/report/html_report_text.h"
#include "hybridtest/report/limit_use.h"
#include "hybridtest/report/plot.h"

namespace hybridtest::report {
namespace {

using nlohmann::json;

constexpr double kLimitWarning = 0.9;  // use of a limit from which the summary flags it

std::string E(std::string_view text) { return EscapeHtml(text); }

// The summary's numbers: 4 significant digits, enough to read a result and its error; whole
// numbers and anything from 10^4 up without an exponent (20000 steps, not 2e+04).
std::string Short(double value) {
  if (!std::isfinite(value)) return FormatNumber(value);
  if (std::abs(value) >= 1e4 && std::abs(value) < 1e15) return fmt::format("{:.0f}", value);
  return fmt::format("{:.4g}", value);
}

json Member(const json& object, const char* key) {
  return object.is_object() && object.contains(key) ? object[key] : json();
}

std::string Badge(const std::string& status) {
  const char* kind = status == "completed" ? "ok" : status == "running" ? "busy" : "bad";
  return fmt::format("<span class=\"badge {}\">{}</span>", kind,
                     E(status.empty() ? "unknown (no sidecar)" : status));
}

std::string Rows(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::string html = "<table class=\"kv\">\n";
  for (const auto& [key, value] : rows) {
    html += "<tr><th>" + E(key) + "</th><td>" + value + "</td></tr>\n";
  }
  return html + "</table>\n";
}

// A value in display units with its unit, e.g. "12.3 mm".
std::string WithUnit(double si_value, const std::string& si_unit, const PlotUnits& units) {
  const std::string label = units.Label(si_unit);
  return Short(si_value * units.Factor(si_unit)) + (label.empty() ? "" : " " + label);
}

std::string ComparisonHeadline(const ComparisonTable& table, const RunLayout& layout,
                               const PlotUnits& units) {
  std::string html = fmt::format(
      "<h3>Against {}</h3>\n<table><tr><th>channel</th><th>max |A&minus;B|</th>"
      "<th>RMS(A&minus;B)</th><th>amplitude A</th><th>amplitude B</th></tr>\n",
      E(table.name_b));
  const auto headline = [&](const std::string& channel) {
    return std::find(layout.coordinates.begin(), layout.coordinates.end(), channel) !=
               layout.coordinates.end() ||
           std::find(layout.restoring.begin(), layout.restoring.end(), channel) !=
               layout.restoring.end();
  };
  for (const ChannelComparison& row : table.rows) {
    if (!headline(row.channel)) continue;
    html += "<tr><td>" + E(row.channel) + "</td>";
    for (double v : {row.max_abs_diff, row.rms_diff, row.amplitude_a, row.amplitude_b}) {
      html += "<td class=\"num\">" + E(WithUnit(v, row.unit, units)) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n<p class=\"note\">A = " + E(table.name_a) + ", B = " +
         E(table.name_b) + "; amplitudes after the first " + E(FormatNumber(table.transient)) +
         " s. Every channel: <a href=\"#comparison\">Comparison</a>.</p>\n";
}

std::string LimitsUsed(const io::RunData& run, const RunLayout& layout, const PlotUnits& units) {
  std::string rows;
  auto row = [&](const std::string& who, const LimitUse& use, const std::string& value) {
    rows += fmt::format(
        "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num{}\">{:.3g} %</td>"
        "<td class=\"num\">{}</td><td>{}</td></tr>\n",
        E(who), E(use.limit), E(value), use.peak >= kLimitWarning ? " bad" : "", 100 * use.peak,
        E(Short(use.peak_t)), E(use.measure));
  };
  std::vector<std::string> served;  // substructures of several slots, once each
  for (const PhysicalChannels& p : layout.physical) {
    if (p.actuator >= 0 &&
        std::find(served.begin(), served.end(), p.substructure) == served.end()) {
      served.push_back(p.substructure);
      for (const SlotLimitUse& s : CalcSlotLimitUse(run, layout, p.substructure)) {
        const bool force = s.use.limit == "max_force";
        row("slot " + s.slot + " (" + p.substructure + ")", s.use,
            WithUnit(s.use.limit_value, force ? "N" : "m", units));
      }
    }
    for (const LimitUse& use : CalcLimitUse(run, p)) {
      const bool force = use.limit.rfind("force", 0) == 0;
      const auto limits = FindLimitsOf(run, p);
      const std::string value =
          use.limit == "stroke" && limits
              ? WithUnit(limits->stroke_min, "m", units) + " … " +
                    WithUnit(limits->stroke_max, "m", units)
              : WithUnit(use.limit_value, force ? "N" : "m", units);
      row(p.actuator >= 0 ? fmt::format("actuator {} of {}", p.actuator + 1, p.substructure)
                          : p.slot,
          use, value);
    }
  }
  if (rows.empty()) return "";
  return "<h3>Safety limits used</h3>\n<table><tr><th>slot or actuator</th><th>limit</th>"
         "<th>limit value</th>"
         "<th>peak use</th><th>at t [s]</th><th>measured as</th></tr>\n" +
         rows + "</table>\n";
}

}  // namespace

std::string SummarySection(const io::RunData& run, const RunLayout& layout,
                           const ComparisonTable* comparison, const PlotUnits& units) {
  const json& meta = run.metadata;
  const json stats = Member(meta, "statistics");
  const Eigen::VectorXd t = RunTime(run);
  auto number = [&](const char* key, const char* suffix) {
    const json v = Member(stats, key);
    return v.is_number() ? E(Short(v.get<double>()) + suffix) : std::string("&ndash;");
  };
  auto duration = [&](const char* key) {
    const json v = Member(stats, key);
    return v.is_number() ? E(FormatDuration(v.get<double>())) : std::string("&ndash;");
  };
  std::vector<std::pair<std::string, std::string>> rows;
  rows.push_back({"Status", Badge(FormatJson(Member(meta, "status")))});
  if (stats.is_object() && stats.contains("stop")) {
    rows.push_back({"Stop", E(FormatJson(Member(stats["stop"], "message")))});
  }
  rows.push_back({"Simulated time", E(fmt::format("{} s to {} s ({} rows)", FormatNumber(t[0]),
                                                  FormatNumber(t[t.size() - 1]), t.size()))});
  rows.push_back({"Steps", number("steps", "")});
  rows.push_back({"Physical evaluations", number("physical_evaluations", "")});
  rows.push_back({"Lab time", duration("lab_time_s")});
  rows.push_back({"Wall time", duration("wall_time_s")});
  rows.push_back({"Slowdown against real time (lab)", number("slowdown", " \u00d7")});
  const json resumes = Member(meta, "resumes");
  rows.push_back({"Resumes", resumes.is_array() && !resumes.empty()
                                 ? fmt::format("{} (<a href=\"#resumes\">list</a>)",
                                               resumes.size())
                                 : std::string("none")});
  std::string html = "<section id=\"summary\"><h2>Summary</h2>\n" + Rows(rows);
  if (!stats.is_object()) {
    html += "<p class=\"note\">The sidecar holds no statistics (the run did not finish, or has no "
            "sidecar).</p>\n";
  }
  if (comparison != nullptr) html += ComparisonHeadline(*comparison, layout, units);
  html += LimitsUsed(run, layout, units);
  return html + "</section>\n";
}

std::string InitialStiffnessSection(const io::RunData& run, const PlotUnits& units) {
  const json k0 = Member(Member(run.metadata, "statistics"), "initial_stiffness");
  if (!k0.is_array() || k0.empty()) return "";
  std::string html =
      "<h3>Initial stiffness K0</h3>\n<table><tr><th>slot</th><th>source</th><th>K0</th>"
      "<th>ramp amplitude</th><th>ramp samples</th></tr>\n";
  for (const json& entry : k0) {
    const std::string slot = FormatJson(Member(entry, "slot"));
    // The slot's force unit over its displacement's: N/m, or N·m/rad for a moment slot.
    std::string unit = "N/m";
    const std::string slot_unit = ChannelUnit(run, slot);
    if (!slot_unit.empty() && slot_unit != "N") unit = slot_unit + "/rad";
    const json value = Member(entry, "k0");
    const json amplitude = Member(entry, "amplitude_m");
    const json samples = Member(entry, "samples_d_m_r_N");
    html += fmt::format(
        "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>"
        "<td class=\"num\">{}</td></tr>\n",
        E(slot), E(FormatJson(Member(entry, "source"))),
        value.is_number() ? E(WithUnit(value.get<double>(), unit, units)) : "&ndash;",
        amplitude.is_number() ? E(WithUnit(amplitude.get<double>(), "m", units)) : "&ndash;",
        samples.is_array() ? std::to_string(samples.size()) : "&ndash;");
  }
  return html + "</table>\n";
}

}  // namespace hybridtest::report
