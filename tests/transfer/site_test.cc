// The site protocol (transfer/site/): a site decides on proposals alone (its gate, nothing
// moves), applies an id at most once (a repeated EXECUTE is answered from its journal), and
// holds when the coordinator is silent beyond its watchdog.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/site/site_client.h"
#include "hybridtest/transfer/site/site_journal.h"
#include "hybridtest/transfer/site/site_server.h"
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

}  // namespace
}  // namespace hybridtest::transfer::site
