// Parsing of the test-only fault injection specs KIND@N.
#include "hybridtest/transfer/bench_faults.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

TEST(BenchFaults, ParsesEveryKind) {
  const std::pair<const char*, FaultKind> cases[] = {
      {"nan", FaultKind::kNan},           {"spike", FaultKind::kSpike},
      {"corrupt", FaultKind::kCorrupt},   {"stale_seq", FaultKind::kStaleSeq},
      {"duplicate", FaultKind::kDuplicate}, {"silence", FaultKind::kSilence},
      {"close", FaultKind::kClose}};
  for (const auto& [name, kind] : cases) {
    const Fault f = ParseFault(std::string(name) + "@12", "--inject");
    EXPECT_EQ(f.kind, kind);
    EXPECT_EQ(f.command, 12);
    EXPECT_EQ(FaultKindName(kind), name);
  }
}

TEST(BenchFaults, RejectsMalformedSpecsNamingTheProblem) {
  for (const char* bad : {"nan", "nan@", "nan@0", "nan@-1", "nan@x", "boom@3", "@3"}) {
    try {
      ParseFault(bad, "--inject");
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("--inject"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos);
    }
  }
}

TEST(BenchFaults, HasFaultMatchesKindAndIndex) {
  const std::vector<Fault> faults = {{FaultKind::kNan, 2}, {FaultKind::kClose, 5}};
  EXPECT_TRUE(HasFault(faults, FaultKind::kNan, 2));
  EXPECT_FALSE(HasFault(faults, FaultKind::kNan, 5));
  EXPECT_FALSE(HasFault(faults, FaultKind::kSpike, 2));
  EXPECT_TRUE(HasFault(faults, FaultKind::kClose, 5));
}

}  // namespace
}  // namespace hybridtest::transfer
