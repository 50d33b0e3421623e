// The OpenFresco client as an element of n = 2 degrees of freedom, against a fake site server
// written here (raw words, decoded with memcpy, not our decoder): the header, the order and
// length of every message, the measurement taken from words 0..n−1 of the replies, and the
// errors for a reply of the wrong length (short, long) and for a scalar command.
#include "hybridtest/transfer/openfresco/client.h"

#include <gtest/gtest.h>

#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::openfresco {
namespace {

constexpr int kDataSize = 256;
constexpr std::size_t kMessageBytes = kDataSize * 8;

// How the fake answers getDisp (7) and getForce (10).
enum class Reply { kExact, kShort, kLong };

// One connection on 127.0.0.1:0: records the header and every client message (whole
// dataSize-word messages), answers 7 with {1.5 + trial d1, 2.5 + trial d2} and 10 with
// {10 · d1, 20 · d2}, each padded to dataSize words (or not, per `reply`).
class FakeSite {
 public:
  explicit FakeSite(Reply reply) : reply_(reply), listener_("127.0.0.1", 0) {
    thread_ = std::thread([this] { Serve(); });
  }
  ~FakeSite() { Wait(); }
  // Waits until the site has served its connection (to the client's 99, or a close).
  void Wait() {
    if (thread_.joinable()) thread_.join();
  }
  std::uint16_t port() const { return listener_.port(); }
  std::vector<std::int32_t> header() {
    std::lock_guard lock(mutex_);
    return header_;
  }
  std::vector<std::vector<double>> messages() {
    std::lock_guard lock(mutex_);
    return messages_;
  }

 private:
  void Serve() {
    Socket s = listener_.Accept(10.0);
    if (!s.is_open()) return;
    std::vector<std::uint8_t> head(44);
    if (ReadBytes(s.fd(), 10.0, head) != ReadStatus::kFrame) return;
    {
      std::lock_guard lock(mutex_);
      header_.resize(11);
      std::memcpy(header_.data(), head.data(), 44);
    }
    std::vector<double> trial(kDataSize, 0.0);
    for (;;) {
      std::vector<std::uint8_t> bytes(kMessageBytes);
      if (ReadBytes(s.fd(), 10.0, bytes) != ReadStatus::kFrame) return;
      std::vector<double> words(kDataSize);
      std::memcpy(words.data(), bytes.data(), kMessageBytes);
      {
        std::lock_guard lock(mutex_);
        messages_.push_back(words);
      }
      const int action = static_cast<int>(words[0]);
      if (action == 3) trial = words;
      if (action == 99) return;
      if (action != 7 && action != 10) continue;
      std::vector<double> out = action == 7
                                    ? std::vector<double>{1.5 + trial[1], 2.5 + trial[2]}
                                    : std::vector<double>{10.0 * trial[1], 20.0 * trial[2]};
      std::size_t words_out = kDataSize;
      if (reply_ == Reply::kShort && action == 7) words_out = 2;     // unpadded: 16 bytes
      if (reply_ == Reply::kLong && action == 7) words_out = kDataSize + 3;
      out.resize(words_out, 0.0);
      std::vector<std::uint8_t> raw(words_out * 8);
      std::memcpy(raw.data(), out.data(), raw.size());
      if (!SendAll(s.fd(), raw, 5.0)) return;
      if (reply_ == Reply::kShort) {  // keep the connection open until the client gives up
        std::vector<std::uint8_t> rest(kMessageBytes);
        ReadBytes(s.fd(), 10.0, rest);
        return;
      }
    }
  }

  Reply reply_;
  Listener listener_;
  std::mutex mutex_;
  std::vector<std::int32_t> header_;
  std::vector<std::vector<double>> messages_;
  std::thread thread_;
};

ClientOptions TwoDofs(std::uint16_t port) {
  ClientOptions o;
  o.port = port;
  o.dofs = 2;
  o.reply_timeout = 1.0;
  return o;
}

TEST(OpenFrescoClient, TwoDofsHeaderMessagesAndMeasurements) {
  FakeSite site(Reply::kExact);
  {
    Client client(TwoDofs(site.port()));
    EXPECT_EQ(client.num_actuators(), 2);
    client.Activate();
    const std::vector<double> commands{0.25, -0.75};  // [mm]
    std::vector<Measurement> out(2);
    client.Execute(commands, out);
    EXPECT_DOUBLE_EQ(out[0].position, 1.75);
    EXPECT_DOUBLE_EQ(out[1].position, 1.75);
    EXPECT_DOUBLE_EQ(out[0].force, 2.5);
    EXPECT_DOUBLE_EQ(out[1].force, -15.0);
    EXPECT_EQ(out[0].lab_time, out[1].lab_time);
    client.Execute(std::vector<double>{1.0, 2.0}, out);
    EXPECT_DOUBLE_EQ(out[1].force, 40.0);
    client.Deactivate();
  }
  site.Wait();  // the 99 is recorded once the site has read it
  // The plain-C header for n = 2: {n,n,n,0,0, 0,0,0,n,0, max(256, 3n+2, n²)}.
  EXPECT_EQ(site.header(), (std::vector<std::int32_t>{2, 2, 2, 0, 0, 0, 0, 0, 2, 0, 256}));
  const auto m = site.messages();
  ASSERT_EQ(m.size(), 7u);  // (trial, 7, 10) × 2, then 99
  const std::vector<double> trial1{3, 0.25, -0.75, 0, 0, 0, 0};
  for (std::size_t i = 0; i < kDataSize; ++i) {
    EXPECT_EQ(m[0][i], i < trial1.size() ? trial1[i] : 0.0) << "trial word " << i;
  }
  const double order[7] = {3, 7, 10, 3, 7, 10, 99};
  for (std::size_t k = 0; k < m.size(); ++k) {
    EXPECT_EQ(m[k][0], order[k]) << "message " << k;
    if (order[k] != 3) {
      for (std::size_t i = 1; i < kDataSize; ++i) ASSERT_EQ(m[k][i], 0.0) << k << ", " << i;
    }
  }
  EXPECT_EQ(m[3][1], 1.0);
  EXPECT_EQ(m[3][2], 2.0);
}

std::string TransferErrorOf(Reply reply) {
  FakeSite site(reply);
  Client client(TwoDofs(site.port()));
  client.Activate();
  std::vector<Measurement> out(2);
  try {
    client.Execute(std::vector<double>{0.1, 0.2}, out);
  } catch (const TransferError& e) {
    EXPECT_FALSE(client.is_connected()) << "the connection is closed after the error";
    return std::string(e.what()) + " @" + std::to_string(site.port());
  }
  return "accepted";
}

TEST(OpenFrescoClient, ShortReplyIsAClearError) {
  const std::string what = TransferErrorOf(Reply::kShort);
  const std::string port = what.substr(what.rfind('@') + 1);
  EXPECT_NE(what.find("127.0.0.1:" + port), std::string::npos) << what;
  EXPECT_NE(what.find("wrong length"), std::string::npos) << what;
  EXPECT_NE(what.find("16 bytes of the reply to getDisp"), std::string::npos) << what;
  EXPECT_NE(what.find("2048 bytes"), std::string::npos) << what;
}

TEST(OpenFrescoClient, LongReplyIsAClearError) {
  const std::string what = TransferErrorOf(Reply::kLong);
  const std::string port = what.substr(what.rfind('@') + 1);
  EXPECT_NE(what.find("127.0.0.1:" + port), std::string::npos) << what;
  EXPECT_NE(what.find("wrong length"), std::string::npos) << what;
  EXPECT_NE(what.find("24 bytes more than the 2048"), std::string::npos) << what;
}

TEST(OpenFrescoClient, ScalarCommandAndBadDofsAreRefused) {
  ClientOptions o;
  o.dofs = 2;
  Client client(o);
  EXPECT_THROW(ExecuteOne(client, 0.1), TransferError);
  std::vector<Measurement> out(3);
  EXPECT_THROW(client.Execute(std::vector<double>{0.1, 0.2, 0.3}, out), TransferError);
  o.dofs = 0;
  EXPECT_THROW(Client{o}, ConfigError);
  o.dofs = kMaxDofs + 1;
  EXPECT_THROW(Client{o}, ConfigError);
  o.dofs = 3;
  EXPECT_NE(Client(o).Describe().find("n = 3"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
