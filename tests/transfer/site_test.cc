// The site protocol (transfer/site/): a site decides on proposals alone (its gate, nothing
// moves), applies an id at most once (a repeated EXECUTE is answered from its journal), and
// holds when the coordinator is silent beyond its watchdog.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/site/site_client.h"
#include "hybridtest/transfer/site/site_journal.h"
#include "hybridtest/transfer/site/site_server.h"
#include "support/small_disk.h"
#include "support/temp_dir.h"
#include "transfer/bench_fake.h"

namespace hybridtest::transfer::site {
namespace {

using testing::FakeBench;

SiteServerOptions SiteOptions(const std::string& journal, double watchdog = 5.0) {
  SiteServerOptions o;
  o.name = "test-site";
  SafetyLimits l;  // ±150 mm, 5 mm per move
  o.limits = {l};
  o.start_positions = {0.0};
  o.watchdog = watchdog;
  o.journal = journal;
  o.journal_max_bytes = std::uintmax_t{16} << 20;  // the start's disk check: 80 MiB free, not 1 GiB
  return o;
}

SiteClientOptions ClientOf(const SiteServer& server) {
  SiteClientOptions o;
  o.name = "r1";
  o.port = server.port();
  o.run = "test-run";
  o.reconnect_wait = 0.5;
  return o;
}

int CountLines(const std::string& text, const std::string& prefix) {
  int n = 0;
  std::size_t at = 0;
  while ((at = text.find("\n" + prefix, at)) != std::string::npos) {
    ++n;
    ++at;
  }
  return n;
}

TEST(Site, ProposeThenExecuteMovesOnceAndARepeatIsAnsweredFromTheRecord) {
  const auto dir = test_support::FreshTempDir("site-once");
  const std::string journal = (dir / "site.journal").string();
  FakeBench bench;
  {
    SiteServer server(bench, SiteOptions(journal));
    testing::ServingThread<SiteServer> serving(server);
    SiteClient client(ClientOf(server));
    client.Activate();
    const std::vector<double> targets = {2.0};  // [mm]
    std::vector<Measurement> out(1);
    client.Propose(targets, 0, 0);
    client.AwaitVerdict();
    client.Release();
    client.Execute(targets, out);
    EXPECT_DOUBLE_EQ(out[0].force, 10.0);
    EXPECT_EQ(bench.commands().size(), 1u);
    // The same transaction again on a new connection (what a reconnect does): no second move.
    SiteClient again(ClientOf(server));
    again.Activate();
    // Its first transaction has seq 1 too: the same key (run, seq) as the one executed.
    again.Propose(targets, 0, 0);
    again.AwaitVerdict();
    again.Release();
    again.Execute(targets, out);
    EXPECT_DOUBLE_EQ(out[0].force, 10.0);
    EXPECT_EQ(bench.commands().size(), 1u) << "an id must be applied at most once";
    EXPECT_EQ(server.executed(), 1);
    client.Deactivate();
  }
  const std::string text = test_support::ReadText(journal);
  EXPECT_EQ(CountLines(text, "execute test-run 1 0 0 0 1 "), 1) << text;
  // A site restarted on the same journal still knows the id.
  SiteJournal reread(journal);
  EXPECT_NE(reread.Find({"test-run", 1, 0, 0, 0}), nullptr);
  EXPECT_EQ(reread.Find({"test-run", 2, 0, 0, 0}), nullptr);
}

TEST(Site, ARefusedProposalMovesNothingAndNamesTheLimit) {
  const auto dir = test_support::FreshTempDir("site-refuse");
  const std::string journal = (dir / "site.journal").string();
  FakeBench bench;
  SiteServer server(bench, SiteOptions(journal));
  testing::ServingThread<SiteServer> serving(server);
  SiteClient client(ClientOf(server));
  client.Activate();
  const std::vector<double> targets = {20.0};  // 20 mm: beyond the 5 mm increment
  client.Propose(targets, 3, 1);
  try {
    client.AwaitVerdict();
    FAIL() << "a move beyond the site's increment limit was accepted";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "max_increment");
    EXPECT_NE(std::string(e.what()).find("site r1"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(bench.commands().empty());
  EXPECT_EQ(server.refusals(), 1);
  client.Deactivate();
  EXPECT_EQ(CountLines(test_support::ReadText(journal), "execute"), 0);
}

TEST(Site, ASilentCoordinatorLeavesTheBenchHolding) {
  FakeBench bench;
  SiteServer server(bench, SiteOptions("", 0.2));
  testing::ServingThread<SiteServer> serving(server);
  SiteClient client(ClientOf(server));
  client.Activate();
  std::vector<Measurement> out(1);
  const std::vector<double> targets = {1.0};
  client.Execute(targets, out);  // proposed and executed by the client alone
  // Bounded wait (no timing asserted): the watchdog holds within a few of its periods.
  for (int i = 0; i < 200 && server.holds() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_GE(server.holds(), 1);
  EXPECT_GE(bench.holds.load(), 1);
  // The next move resumes the held bench.
  const std::vector<double> next = {2.0};
  client.Execute(next, out);
  EXPECT_EQ(bench.commands().size(), 2u);
  client.Deactivate();
}

TEST(Site, ABenchThatCannotReadAnswersNoPositionAndTheLinkGoesOn) {
  FakeBench bench;  // it cannot read its position without moving
  SiteServer server(bench, SiteOptions(""));
  testing::ServingThread<SiteServer> serving(server);
  SiteClient client(ClientOf(server));
  client.Activate();
  EXPECT_FALSE(client.ReadAll().has_value());
  EXPECT_TRUE(bench.commands().empty());
  std::vector<Measurement> out(1);
  const std::vector<double> targets = {1.0};
  client.Execute(targets, out);
  EXPECT_EQ(bench.commands().size(), 1u);
  EXPECT_EQ(client.reconnects(), 0);
  client.Deactivate();
}

// A site on a FakeBench with its journal in a fresh folder, served, and a client connected.
struct JournaledSite {
  JournaledSite(const std::string& name, const std::function<void(SiteServerOptions&)>& set)
      : journal((test_support::FreshTempDir(name) / "site.journal").string()),
        server(bench, Options(journal, set)),
        serving(server),
        client(ClientOf(server)) {
    client.Activate();
  }
  static SiteServerOptions Options(const std::string& journal,
                                   const std::function<void(SiteServerOptions&)>& set) {
    SiteServerOptions o = SiteOptions(journal);
    set(o);
    return o;
  }
  std::string journal;
  FakeBench bench;
  SiteServer server;
  testing::ServingThread<SiteServer> serving;
  SiteClient client;
};

// The journal's bound (journal_max_bytes): past it, a proposal is refused (limit "journal",
// the fix named) and the site holds; the file stays within the bound and every executed
// transaction is in it.
TEST(Site, AFullJournalRefusesProposalsAndHoldsWithEveryExecuteJournaled) {
  JournaledSite site("site-journal-full",
                     [](SiteServerOptions& o) { o.journal_max_bytes = 4000; });
  auto& [journal, bench, server, serving, client] = site;
  std::vector<Measurement> out(1);
  std::string stop;
  for (int k = 1; k <= 200 && stop.empty(); ++k) {
    const std::vector<double> targets = {0.01 * k};  // [mm]
    try {
      client.Execute(targets, out);
    } catch (const SafetyStop& e) {
      EXPECT_EQ(e.limit(), "journal");
      stop = e.what();
    }
  }
  ASSERT_FALSE(stop.empty()) << "the journal grew without bound";
  EXPECT_NE(stop.find("journal_max_mb"), std::string::npos) << stop;
  EXPECT_GE(server.holds(), 1);
  client.Deactivate();
  const std::string text = test_support::ReadText(journal);
  EXPECT_LE(text.size(), 4000u);
  EXPECT_GT(server.executed(), 0);
  EXPECT_EQ(CountLines(text, "execute "), server.executed()) << text;
  EXPECT_EQ(static_cast<long>(bench.commands().size()), server.executed());
}

// refusals_per_minute: a flood of refused proposals (any coordinator; UI-SimCor's has no
// token) is answered but journaled only up to the rate, and the site holds.
TEST(Site, AFloodOfRefusedProposalsIsNotJournaledLineByLine) {
  JournaledSite site("site-refusal-flood",
                     [](SiteServerOptions& o) { o.refusals_per_minute = 5; });
  auto& [journal, bench, server, serving, client] = site;
  int refused = 0;
  for (int k = 0; k < 50; ++k) {
    const std::vector<double> targets = {20.0 + k};  // beyond the 5 mm increment
    client.Propose(targets, k, 0);
    try {
      client.AwaitVerdict();
    } catch (const SafetyStop& e) {
      EXPECT_EQ(e.limit(), "max_increment");
      ++refused;
    }
  }
  EXPECT_EQ(refused, 50);
  EXPECT_EQ(server.refusals(), 50);
  EXPECT_GE(server.holds(), 1);
  EXPECT_TRUE(bench.commands().empty());
  client.Deactivate();
  const std::string text = test_support::ReadText(journal);
  EXPECT_EQ(CountLines(text, "propose "), 5) << text;
  EXPECT_EQ(CountLines(text, "hold more than 5 refused proposals"), 1) << text;
}

// The journal's bound against its disk: on a disk of 128 MiB, a site whose journal may grow to
// 1 GiB (journal_max_mb's default) refuses to start, naming the journal, its bound, the free
// room and the fix, and writes nothing there; a bound that fits (16 MiB) starts.
TEST(Site, AJournalBoundBeyondTheFreeRoomIsRefusedAtStart) {
  const auto dir = test_support::FreshTempDir("site-journal-disk");
  const std::string journal = (dir / "disk" / "site.journal").string();
  const auto answer = test_support::RunOnSmallDisk(dir / "disk", std::size_t{128} << 20, [&] {
    std::string said;
    FakeBench bench;
    for (const std::uintmax_t bound : {std::uintmax_t{1} << 30, std::uintmax_t{16} << 20}) {
      SiteServerOptions o = SiteOptions(journal);
      o.journal_max_bytes = bound;
      try {
        SiteServer server(bench, o);
        said += "started\n";
      } catch (const ConfigError& e) {
        said += std::string(e.what()) + "\nleft: " +
                (std::filesystem::exists(journal) ? "a journal" : "nothing") + "\n";
      }
    }
    return said;
  });
  if (!answer) GTEST_SKIP() << "no private mount namespace here (unshare)";
  const std::vector<std::string> parts = {
      journal + ": site test-site's journal would write about 1073.7 MB up to its bound "
                "journal_max_mb = 1024, but ",
      " free (and ", "lower site.journal_max_mb", "\nleft: nothing\nstarted\n"};
  for (const std::string& part : parts) {
    EXPECT_NE(answer->find(part), std::string::npos) << "missing: " << part << "\n" << *answer;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::transfer::site
