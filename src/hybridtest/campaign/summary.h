#pragma once
// The campaign's results: DIR/summary.csv (one row per case, in campaign order), the error
// metrics against the reference case, and the figures of the metrics against the varied
// parameters (DIR/figures/, drawn with the project's gnuplot renderer).
//
// summary.csv: case, one column per varied key path, status (finished | failed | pending),
// duration_s (wall time of the case [s]), worker, one column per metric (the journal's unit
// of its channel; empty where it cannot be computed), for `plan` cases recommendation,
// evaluations, plan_error [-] and lab_time_s [s], and last the error message. Numbers are
// written as the shortest text that reads back to the same double; text fields are quoted
// (RFC 4180) when they hold a comma, a quote or a line break.
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/campaign/case_runner.h"

namespace hybridtest::campaign {

// Fills every error(CH) metric of the finished cases: max over the journal's rows of
// |CH − CH of the reference case| (same units as CH). NaN when the reference did not finish or
// the two journals do not have the same rows (a different step). Reads the journals.
void FillErrorMetrics(const Campaign& campaign, const std::string& out_dir,
                      std::vector<std::optional<CaseResult>>& results);

// The text of summary.csv (results[i] is case i's, or nullopt when it has not run).
std::string SummaryCsv(const Campaign& campaign,
                       const std::vector<std::optional<CaseResult>>& results);

// Renders one figure per numeric metric and numeric varied parameter into DIR/figures/
// (metric against the parameter, one line per combination of the other parameters). Returns
// the files written. Throws IoError if gnuplot fails.
std::vector<std::string> WriteCampaignFigures(
    const Campaign& campaign, const std::vector<std::optional<CaseResult>>& results,
    const std::string& out_dir);

}  // namespace hybridtest::campaign
