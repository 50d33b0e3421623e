#pragma once
// Journal rows as the run state and the journal checks compare them (run_state.cc,
// run_state_journal.cc).
#include <string>
#include <vector>

namespace hybridtest::runner {

// Two journal rows are the same if their values' bits are, NaN matching NaN.
bool SameJournalValues(const std::vector<double>& a, const std::vector<double>& b);
// The first values of a row, for messages ("0.1,0.002,...").
std::string DescribeRow(const std::vector<double>& row);
// One journal line's values: every field that is not a number (an empty field, a damaged
// one) reads as NaN, which matches no committed value.
void ParseJournalLine(const std::string& line, std::vector<double>& values);

}  // namespace hybridtest::runner
