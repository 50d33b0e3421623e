#pragma once
// A campaign: one base run config and its variations, each case a `simulate`, a `run` on an
// in-process bench (dummy or emulated) or a `plan` (docs/campaigns.md). The campaign file:
//
//   base: ../rotor/numerical.yaml   # the run config every case starts from (relative to here)
//   command: simulate               # simulate | run | plan
//   set:                            # overrides for every case (key paths of the base config)
//     duration: 2.0
//   grid:                           # every combination of the values (the product)
//     model.parameters.f_w: [50, 100, 150]
//     model.parameters.blade1.k_b: [5250, 7200]
//   table: cases.csv                # a CSV of cases: a header of key paths (and an optional
//                                   # `id` column), one case per line
//   seeds: {key: K, values: [...]}  # or {key: K, count: N, first: 1}: one case per seed,
//                                   # e.g. K = substructures.r1.transfer.bench.seed
//   metrics: [max_abs(q1), rms(q1), final(u4), error(q1)]
//   reference: {model.parameters.f_w: 100}  # the case error() compares against
//   plan: {tolerance: 0.01, emulate: bench.yaml}
//   figures: true
//
// The cases are the product table rows × grid × seeds (an absent part counts as one empty
// case), in that order. A key path is split at dots, except that everything after a
// `parameters` segment is one key (`model.parameters.blade1.k_b` sets the parameter
// `blade1.k_b`). A value is a YAML scalar, written into the case's config as given.
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

namespace hybridtest::campaign {

enum class CaseCommand { kSimulate, kRun, kPlan };
const char* CaseCommandName(CaseCommand command);

// One named quantity of a case's summary row, from its journal.
struct MetricSpec {
  enum Kind { kMaxAbs, kMax, kMin, kRms, kFinal, kError } kind = kMaxAbs;
  std::string channel;  // a journal channel, e.g. "q1"
  std::string name;     // as written, e.g. "max_abs(q1)": the summary's column
};

struct CaseSpec {
  std::string id;  // the folder under cases/ and the summary's first column
  // (key path, value as written), the varied parameters in campaign order.
  std::vector<std::pair<std::string, std::string>> params;
};

struct Campaign {
  std::string path;       // the campaign file
  std::string text;       // its verbatim text
  std::string base_path;  // the base run config, as resolved against the campaign's folder
  std::string base_text;  // its verbatim text
  CaseCommand command = CaseCommand::kSimulate;
  std::vector<std::pair<std::string, std::string>> set;  // overrides for every case
  std::vector<std::string> varied;  // the varied key paths (the summary's parameter columns)
  std::vector<CaseSpec> cases;
  std::vector<MetricSpec> metrics;
  int reference = -1;     // index of the reference case (error() metrics), -1 if none
  double plan_tolerance = 0.01;  // plan: largest acceptable relative error [-]
  std::string plan_emulate;      // plan: stand-in bench file (resolved), or ""
  bool figures = true;
};

// Reads and checks a campaign file and its base config and table. Throws ConfigError naming
// file:line, the key and the fix (an unknown key, an empty grid, a duplicate case id, ...).
Campaign LoadCampaign(const std::string& path);

// Sets `key_path` (see above) to the scalar `value` in `root`, creating mappings on the way.
// Throws ConfigError if a segment on the way is a value, not a mapping.
void SetKeyPath(YAML::Node root, const std::string& key_path, const std::string& value);
std::vector<std::string> SplitKeyPath(const std::string& key_path);

// The complete run config of case `index`, as YAML text, to be written to `case_dir`: the
// base with the `set` and the case's values applied, `output.csv` removed (the campaign gives
// the journal's path) and the files the base names (model file, bench and token files)
// rewritten relative to case_dir. A key under `substructures.SLOT.transfer.bench.` of a slot
// whose emulated bench is a file (`transfer.config`) first copies that file's `bench:` mapping
// into the case's config, so a campaign can vary a bench's seed or specimen.
std::string CaseConfigText(const Campaign& campaign, int index, const std::string& case_dir);

// True if `id` may name a case folder: 1..120 characters of [A-Za-z0-9._=+-], not starting
// with a dot.
bool IsValidCaseId(const std::string& id);

}  // namespace hybridtest::campaign
