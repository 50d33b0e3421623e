// A site driven by a scripted client speaking UI-SimCor's ASCII protocol (simcor_codec.h) on
// 127.0.0.1: the same transaction rules as the site protocol (a refusal moves nothing, an id
// is applied at most once, the journal), on the same server and port.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/site/site_client.h"
#include "hybridtest/transfer/site/site_server.h"
#include "hybridtest/transfer/socket.h"
#include "support/temp_dir.h"
#include "transfer/bench_fake.h"
#include "transfer/serving_thread.h"

namespace hybridtest::transfer::site {
namespace {

using testing::FakeBench;

SiteServerOptions SimcorSite(const std::string& journal, bool simcor = true) {
  SiteServerOptions o;
  o.name = "simcor-site";
  o.limits = {SafetyLimits{}};  // ±150 mm, 5 mm per move
  o.start_positions = {0.0};
  o.journal = journal;
  o.journal_max_bytes = std::uintmax_t{16} << 20;  // the start's disk check: 80 MiB free, not 1 GiB
  o.simcor = simcor;
  return o;
}

// A UI-SimCor coordinator as a script: one line out, one line back (bounded reads).
class LineClient {
 public:
  explicit LineClient(std::uint16_t port) : socket_(ConnectTcp("127.0.0.1", port, 2.0)) {}
  void Send(const std::string& line) {
    EXPECT_TRUE(SendAll(socket_.fd(), {line.begin(), line.end()}, 2.0)) << line;
  }
  std::string Ask(const std::string& line) {
    Send(line);
    // One exit, the answer built in place (GCC 12 at -O1 sees a false array-bounds error in
    // returning `answer + "..."`).
    std::string answer;
    answer.reserve(64);
    std::vector<std::uint8_t> one(1);
    while (answer.size() < 8192) {
      if (ReadBytes(socket_.fd(), 5.0, one) != ReadStatus::kFrame) {
        answer.append("<closed>");
        break;
      }
      if (one[0] == '\n') break;
      answer.push_back(static_cast<char>(one[0]));
    }
    return answer;
  }
  // True if the site closes the connection (within a bounded read of what it sends first).
  bool Closed() {
    std::vector<std::uint8_t> one(1);
    for (int n = 0; n < 100000; ++n) {
      if (ReadBytes(socket_.fd(), 5.0, one) != ReadStatus::kFrame) return true;
    }
    return false;
  }

 private:
  Socket socket_;
};

std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == '\t') {
      out.emplace_back();
    } else {
      out.back().push_back(c);
    }
  }
  return out;
}

std::string Id(int step) { return "trans20260101120000." + std::to_string(step) + "[" +
                                  std::to_string(step) + " 0 0]"; }

std::string ProposeLine(const std::string& id, double target_mm) {
  return "propose\t" + id + "\tMDL-00-01:LBCB1\tx\tdisplacement\t" + std::to_string(target_mm) +
         "\n";
}

TEST(SiteSimcor, AScriptedUiSimCorClientDrivesASiteThrough100Steps) {
  const auto dir = test_support::FreshTempDir("site-simcor");
  const std::string journal = (dir / "site.journal").string();
  FakeBench bench;
  SiteServer server(bench, SimcorSite(journal));
  testing::ServingThread<SiteServer> serving(server);
  LineClient client(server.port());
  EXPECT_EQ(Fields(client.Ask("open-session\tMDL-00-01\tsimcor\n"))[0], "OK");
  double last = 0.0;
  for (int step = 1; step <= 100; ++step) {
    last = std::round(3000.0 * std::sin(0.1 * step)) / 1000.0;  // [mm], < 0.4 mm per step
    const std::string id = Id(step);
    const auto proposed = Fields(client.Ask(ProposeLine(id, last)));
    ASSERT_EQ(proposed.size(), 4u) << step;
    ASSERT_EQ(proposed[0], "OK") << proposed[3];
    EXPECT_EQ(proposed[2], id);
    EXPECT_EQ(client.Ask("execute\t" + id + "\n"), "OK\t0\t" + id + "\texecuted");
    // The query: the control point's displacement and force, from the record.
    const auto point = Fields(client.Ask("get-control-point\t" + id + "\tMDL-00-01:LBCB1\n"));
    ASSERT_EQ(point.size(), 10u) << step;
    EXPECT_EQ(point[3], "MDL-00-01:LBCB1");
    EXPECT_EQ(point[5], "displacement");
    EXPECT_DOUBLE_EQ(std::stod(point[6]), last);
    EXPECT_EQ(point[8], "force");
    EXPECT_DOUBLE_EQ(std::stod(point[9]), FakeBench::kStiffness * last);
  }
  EXPECT_EQ(bench.commands().size(), 100u);
  EXPECT_EQ(server.executed(), 100);
  // A repeated execute is answered from the record: nothing moves.
  EXPECT_EQ(Fields(client.Ask("execute\t" + Id(50) + "\n"))[3],
            "executed before: answered from the record, nothing moved");
  EXPECT_EQ(bench.commands().size(), 100u) << "an id must be applied at most once";
  const auto dummy = Fields(client.Ask("get-control-point\tdummy\tMDL-00-01:LBCB1\n"));
  ASSERT_EQ(dummy.size(), 10u);
  EXPECT_DOUBLE_EQ(std::stod(dummy[6]), std::round(3000.0 * std::sin(5.0)) / 1000.0);
  // A malformed line is answered NOT OK, naming the field; the connection stays.
  const auto bad = Fields(client.Ask("execute\ttrans1[1 x 0]\n"));
  EXPECT_EQ(bad[0], "NOT OK");
  EXPECT_NE(bad[3].find("substep"), std::string::npos) << bad[3];
  // A refused proposal moves nothing, and its execute is refused too.
  const std::string far = Id(101);
  const auto refused = Fields(client.Ask(ProposeLine(far, last + 20.0)));
  ASSERT_EQ(refused.size(), 4u);
  EXPECT_EQ(refused[0], "NOT OK");
  EXPECT_NE(refused[3].find("max_increment"), std::string::npos) << refused[3];
  EXPECT_EQ(refused[3].find("MDL"), std::string::npos);
  EXPECT_EQ(Fields(client.Ask("execute\t" + far + "\n"))[0], "NOT OK");
  EXPECT_EQ(bench.commands().size(), 100u);
  EXPECT_EQ(server.refusals(), 1);
  // close-session holds the bench and ends the connection.
  const int holds = bench.holds.load();
  EXPECT_EQ(Fields(client.Ask("close-session\tdummy\tMDL\tsimcor\n"))[0], "OK");
  EXPECT_GT(bench.holds.load(), holds);
  // The same port still serves the site protocol.
  SiteClientOptions binary;
  binary.name = "r1";
  binary.port = server.port();
  binary.run = "test-run";
  SiteClient coordinator(binary);
  coordinator.Activate();
  std::vector<Measurement> out(1);
  const std::vector<double> next = {last + 1.0};
  coordinator.Execute(next, out);
  EXPECT_DOUBLE_EQ(out[0].position, last + 1.0);
  coordinator.Deactivate();
  const std::string text = test_support::ReadText(journal);
  EXPECT_NE(text.find("propose trans20260101120000.101-101-0-0 1 101 0 0 refuse:max_increment"),
            std::string::npos) << text;
  EXPECT_EQ(text.find("execute trans20260101120000.101-101-0-0"), std::string::npos);
  EXPECT_NE(text.find("execute trans20260101120000.100-100-0-0 1 100 0 0 1 "), std::string::npos);
}

TEST(SiteSimcor, IsRefusedUnlessTheSiteAcceptsItAndWithoutAToken) {
  FakeBench bench;
  {
    SiteServer server(bench, SimcorSite("", false));
    testing::ServingThread<SiteServer> serving(server);
    LineClient client(server.port());
    // Not a bench-protocol frame: the site closes the connection.
    client.Send(ProposeLine(Id(1), 1.0));
    EXPECT_TRUE(client.Closed());
    EXPECT_TRUE(bench.commands().empty());
  }
  SiteServerOptions with_token = SimcorSite("");
  with_token.token = "0123456789abcdef0123";
  try {
    SiteServer server(bench, with_token);
    FAIL() << "a UI-SimCor site with a token was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--simcor"), std::string::npos) << e.what();
  }
}

// get-control-point dummy before any execute: where the bench is now, read without moving
// (here a bench that cannot read so: NOT OK saying that, nothing moved, the link kept).
TEST(SiteSimcor, ADummyQueryBeforeAnyExecuteReadsTheBenchNow) {
  FakeBench bench;
  SiteServer server(bench, SimcorSite(""));
  testing::ServingThread<SiteServer> serving(server);
  LineClient client(server.port());
  const std::string answer = client.Ask("get-control-point\tdummy\tMDL-00-01:LBCB1\n");
  EXPECT_EQ(answer.rfind("NOT OK\t", 0), 0u) << answer;
  EXPECT_NE(answer.find("cannot read its position without moving"), std::string::npos) << answer;
  EXPECT_TRUE(bench.commands().empty());
  EXPECT_EQ(client.Ask("open-session\n").rfind("OK\t", 0), 0u);
}

}  // namespace
}  // namespace hybridtest::transfer::site
