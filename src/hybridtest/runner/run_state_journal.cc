// See run_state.h: the journal read beside a run state (its rows, whether the state is the
// latest, cutting it back); run_state_rows.h.
#include <fmt/core.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/csv.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/runner/run_state.h"
#include "hybridtest/runner/run_state_rows.h"

namespace hybridtest::runner {

bool SameJournalValues(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) && std::isnan(b[i])) continue;
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) return false;
  }
  return true;
}

std::string DescribeRow(const std::vector<double>& row) {
  std::string text;
  for (std::size_t i = 0; i < row.size() && i < 6; ++i) {
    text += fmt::format("{}{}", i == 0 ? "" : ",", row[i]);
  }
  return text + (row.size() > 6 ? ",..." : "");
}

void ParseJournalLine(const std::string& line, std::vector<double>& values) {
  values.clear();
  for (const std::string_view field : io::SplitCsvLine(line)) {
    values.push_back(io::ParseCsvNumber(field).value_or(std::numeric_limits<double>::quiet_NaN()));
  }
}

JournalRows ReadJournalRows(const std::string& csv_path, const std::vector<long>& indices) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  JournalRows result;
  std::string line;
  long index = -1;  // the header is line −1
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line, not a row
    if (index >= 0 && std::find(indices.begin(), indices.end(), index) != indices.end()) {
      std::vector<double> values;
      ParseJournalLine(line, values);
      result.rows.emplace(index, std::move(values));
    }
    ++index;
  }
  result.complete = std::max(index, 0L);
  return result;
}

namespace {

// Where a journal row's columns are, from the state: t, x (nx), r (m), then command, position,
// force and lab time of each of `actuators` physical actuators, then `forces` constraint forces.
struct RowLayout {
  std::size_t nx = 0, m = 0, actuators = 0, forces = 0;
};

RowLayout LayoutOf(const RunState& s) {
  RowLayout layout;
  layout.nx = s.scheme.at("x").size();
  layout.m = s.scheme.at("r").size();
  layout.forces = static_cast<std::size_t>(s.constraint_forces);
  const std::size_t fixed = 1 + layout.nx + layout.m + layout.forces;
  if (s.row.size() > fixed && (s.row.size() - fixed) % 4 == 0) {
    layout.actuators = (s.row.size() - fixed) / 4;
  }
  return layout;
}

// The journal read once: the rows asked for, and which rows are committed points with a
// specimen sample (Session::FillRow: only a committed row carries the actuators' exchange;
// an intermediate row and an uncommitted one have NaN there).
struct JournalScan {
  JournalRows rows;
  long committed_before = 0;  // committed rows among rows 0..state_rows−1
  long committed_after = 0;   // committed rows from row state_rows on
  long last_committed = -1;   // index of the last committed row
};

JournalScan ScanJournal(const std::string& csv_path, const std::vector<long>& indices,
                        const RowLayout& layout, long state_rows) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  JournalScan scan;
  std::string line;
  long index = -1;  // the header is line −1
  std::vector<double> values;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line, not a row
    if (index >= 0) {
      ParseJournalLine(line, values);
      if (std::find(indices.begin(), indices.end(), index) != indices.end()) {
        scan.rows.rows.emplace(index, values);
      }
      if (layout.actuators > 0 && values.size() == 1 + layout.nx + layout.m + 4 * layout.actuators + layout.forces) {
        bool committed = true;
        for (std::size_t k = 0; k < layout.actuators && committed; ++k) {
          committed = !std::isnan(values[1 + layout.nx + layout.m + 4 * k]);
        }
        if (committed) {
          (index < state_rows ? scan.committed_before : scan.committed_after) += 1;
          scan.last_committed = index;
        }
      }
    }
    ++index;
  }
  scan.rows.complete = std::max(index, 0L);
  return scan;
}

}  // namespace

void VerifyRunStateAgainstJournal(const RunState& state, const std::string& csv_path) {
  const std::string state_path = RunStatePath(csv_path);
  const RowLayout layout = LayoutOf(state);
  const JournalScan scan =
      ScanJournal(csv_path, {state.journal_rows - 1, state.rows - 1, 1}, layout, state.rows);
  const JournalRows& j = scan.rows;
  auto refuse = [&](const std::string& what) {
    throw ConfigError(fmt::format(
        "{}: the run state {} does not belong to this journal: {}. Resume refuses, and nothing "
        "was changed: restore the journal and the state the run wrote together (a journal or a "
        "state copied from another run, edited, or cut cannot be continued)",
        csv_path, state_path, what));
  };
  if (j.complete < state.journal_rows) {
    refuse(fmt::format("the journal has {} rows, but held {} when the state was saved",
                       j.complete, state.journal_rows));
  }
  if (state.journal_last_row) {
    const auto& row = j.rows.at(state.journal_rows - 1);
    if (!SameJournalValues(row, *state.journal_last_row)) {
      refuse(fmt::format("its row {} is {} but was {} when the state was saved",
                         state.journal_rows - 1, DescribeRow(row), DescribeRow(*state.journal_last_row)));
    }
  }
  if (const auto it = j.rows.find(state.rows - 1); it != j.rows.end()) {
    if (!SameJournalValues(it->second, state.row)) {
      refuse(fmt::format("the committed row {} is {} in the journal but {} in the state",
                         state.rows - 1, DescribeRow(it->second), DescribeRow(state.row)));
    }
  } else if (j.complete != state.rows - 1) {
    refuse(fmt::format("the journal has {} rows; the state's committed row is row {}",
                       j.complete, state.rows - 1));
  }
  // A fixed-step Runge-Kutta run (its scheme named after its tableau: not one of the
  // operator-splitting schemes) commits step n at t = n·h exactly (runge_kutta_scheme.cc), h
  // being row 1's t.
  const std::string scheme_name = state.scheme.value("scheme", std::string());
  if (scheme_name != "alpha-os" && scheme_name != "mr-os" &&
      state.scheme.at("step").get<long>() >= 1 && j.rows.count(1) != 0 &&
      !j.rows.at(1).empty()) {
    const double h = j.rows.at(1)[0];
    const long n = state.scheme.at("step").get<long>();
    const double t = state.scheme.at("t").get<double>();
    if (t != static_cast<double>(n) * h) {
      refuse(fmt::format("its step {} and time t = {} s disagree: the run's fixed step is {} s "
                         "(the journal's row 1), so step {} is at t = {} s",
                         n, t, h, n, static_cast<double>(n) * h));
    }
  }
  // The journal is the truth: the state must be the latest. A run with a physical slot saves
  // its state at every committed row, before the row (a real-time run when it stops, at its
  // last committed row): no committed row may follow the state's. An older state would cut
  // those rows and re-run their steps on the specimen.
  const long step = state.scheme.at("step").get<long>();
  auto refuse_older = [&](const std::string& what) {
    throw ConfigError(fmt::format(
        "{}: the run state {} is older than the journal: {}. Resuming from it would cut "
        "committed rows and run their steps again{}. Resume refuses, and nothing was changed "
        "or moved: restore the run state the run wrote last (an older copy of a state, or one "
        "edited and re-checksummed, cannot be continued)",
        csv_path, state_path, what, layout.actuators > 0 ? " on the specimen" : ""));
  };
  if (layout.actuators > 0) {
    if (scan.committed_after > 0) {
      refuse_older(fmt::format(
          "it belongs to committed row {} (step {}, t = {} s), but the journal holds {} "
          "committed row{} after it, the last being row {}",
          state.rows - 1, step, state.row.empty() ? 0.0 : state.row[0], scan.committed_after,
          scan.committed_after == 1 ? "" : "s", scan.last_committed));
    }
    // Every step commits one row with a specimen sample: rows 0..rows−1 hold step + 1 of them
    // (the state's own row counts where a crash lost it).
    const long committed = scan.committed_before + (j.complete == state.rows - 1 ? 1 : 0);
    if (committed != step + 1) {
      refuse(fmt::format("it says step {}, but the journal's rows 0 to {} hold {} committed "
                         "steps' rows (step + 1 = {} expected)",
                         step, state.rows - 1, committed, step + 1));
    }
  } else if (state.scheme.value("scheme", std::string()) != "mr-os") {
    // Numerical: the state is saved every kStateInterval rows (and at the end), so it may be
    // older than the journal by less than two intervals; re-running those steps moves nothing.
    constexpr long kStateInterval = 1000;
    if (j.complete - state.rows >= 2 * kStateInterval) {
      refuse_older(fmt::format("it belongs to row {}, but the journal holds {} rows; a "
                               "numerical run saves its state every {} rows",
                               state.rows - 1, j.complete, kStateInterval));
    }
  }
}

long CutJournalToRows(const std::string& csv_path, long rows) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  // Offset after the header and `rows` complete lines; count the complete lines after it.
  std::string line;
  std::int64_t keep = -1;
  long complete = -1;  // data rows (the header is line 0)
  std::int64_t offset = 0;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line
    offset += static_cast<std::int64_t>(line.size()) + 1;
    ++complete;
    if (complete == rows) keep = offset;
  }
  if (complete <= rows) return 0;
  in.close();
  const int fd = ::open(csv_path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd >= 0) {
    // Never a live run's journal (run_lock.h): refused if another process writes it.
    try {
      io::LockJournalFile(fd, csv_path);
    } catch (...) {
      ::close(fd);
      throw;
    }
  }
  if (fd < 0 || ::ftruncate(fd, static_cast<off_t>(keep)) != 0 || ::fsync(fd) != 0) {
    const std::string error = io::OsError();
    if (fd >= 0) ::close(fd);
    throw IoError(fmt::format("{}: cannot cut the journal back to its row {}: {}", csv_path,
                              rows - 1, error));
  }
  ::close(fd);
  return complete - rows;
}

}  // namespace hybridtest::runner
