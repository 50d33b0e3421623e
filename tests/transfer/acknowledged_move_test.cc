// The acknowledged move of a PLC (transfer/acknowledged_move.h) against a fake protocol: the
// sequence, each check (ack timeout, an ack from another client, fault, enable, holding, the
// first exchange's plausibility, following error, stale acknowledgement), the hold on every
// failure and the refusal after it, and the stops' values in SI.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/acknowledged_move.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {
namespace {

// A controller in memory: it settles at the command (plus `offset`) once `reads_to_ack` reads
// have passed, and reports what the test sets.
class FakePlc final : public AckController {
 public:
  explicit FakePlc(std::size_t n) : state(n), offset(n, 0.0) {}

  void Write(std::span<const double> commands,
             std::span<const std::uint64_t> sequences) override {
    ++writes;
    if (refuse_write) throw TransferError("the fake refused the write");
    sent.assign(sequences.begin(), sequences.end());
    commanded.assign(commands.begin(), commands.end());
    reads_since_write = 0;
  }
  void Read(std::vector<AckReading>& out, const std::string&) override {
    ++reads;
    if (fail_read) throw TransferError("the fake lost the link");
    if (++reads_since_write >= reads_to_ack && !silent) {
      for (std::size_t k = 0; k < state.size(); ++k) {
        if (!stale) state[k].position = commanded[k] + offset[k];
        state[k].ack = other_client ? 42 : sent[k];
      }
    }
    out = state;
  }
  void Wait() override { ++waits; }
  void Hold() noexcept override { ++holds; }

  std::string Name() const override { return "the fake PLC"; }
  std::string Subject(std::size_t k) const override {
    return state.size() == 1 ? Name() : "the fake PLC: actuator " + std::to_string(k + 1);
  }
  std::string Describe(std::size_t k) const override {
    return "position " + std::to_string(state[k].position);
  }
  std::string Where(Flag flag, std::size_t) const override {
    return flag == Flag::kFault ? "bit F" : flag == Flag::kEnabled ? "bit E" : "bit H";
  }
  std::string Sequences(std::span<const std::uint64_t> s) const override {
    return "sequence " + ValueList(s);
  }
  std::string Ack(std::size_t, std::uint64_t ack) const override {
    return "sequence " + std::to_string(ack);
  }
  std::string Held() const override { return "the fake holds"; }
  std::string PlausibilityHint() const override { return "check the fake's scale"; }

  std::vector<AckReading> state;
  std::vector<double> offset;             // measured − reached, bench length unit
  std::vector<double> commanded;
  std::vector<std::uint64_t> sent;
  int reads_to_ack = 1, reads_since_write = 0;
  bool refuse_write = false, fail_read = false, silent = false, stale = false;
  bool other_client = false;
  int writes = 0, reads = 0, waits = 0, holds = 0;
};

BenchUnits Millimetres() {
  BenchUnits u;
  u.metres_per_length_unit = 1e-3;
  u.length_name = "mm";
  return u;
}

// A move of n actuators in mm with the defaults (settling window 0.05 mm, following error
// 0.2 mm, plausibility 1 mm and 1 MN) and a short ack timeout.
AcknowledgedMove MoveOf(std::size_t n, std::uint64_t modulus = 65536) {
  ControllerOptions o;
  o.ack_timeout = 0.05;
  return AcknowledgedMove(o, Millimetres(), std::vector<std::uint64_t>(n, modulus), false,
                          "fake transfer");
}

// Move() of one command; the TransferError's message ("" if none).
std::string Failure(AcknowledgedMove& move, FakePlc& plc, double command) {
  std::array<Measurement, 1> out;
  const std::array<double, 1> c{command};
  try {
    move.Move(c, out, plc, true, "");
  } catch (const TransferError& e) {
    return e.what();
  }
  return "";
}

Measurement One(AcknowledgedMove& move, FakePlc& plc, double command) {
  std::array<Measurement, 1> out;
  const std::array<double, 1> c{command};
  move.Move(c, out, plc, true, "");
  return out[0];
}

SafetyStop StopOf(AcknowledgedMove& move, FakePlc& plc, double command) {
  try {
    One(move, plc, command);
  } catch (const SafetyStop& e) {
    return e;
  }
  ADD_FAILURE() << "no SafetyStop";
  return SafetyStop("none", 0, 0, 0, 0, {}, "");
}

TEST(AcknowledgedMove, SendsTheNextSequenceAndReturnsTheSettledReading) {
  FakePlc plc(1);
  plc.state[0].force = 12.5;
  AcknowledgedMove move = MoveOf(1, 4);
  move.Start(std::vector<std::uint64_t>{2});
  Measurement m = One(move, plc, 1.5);
  EXPECT_EQ(plc.sent[0], 3u);
  EXPECT_EQ(m.position, 1.5);
  EXPECT_EQ(m.force, 12.5);
  m = One(move, plc, 1.6);
  EXPECT_EQ(plc.sent[0], 0u) << "3 + 1 modulo 4";
  EXPECT_EQ(plc.holds, 0);
  // Polls until the ack, waiting between reads.
  plc.reads_to_ack = 3;
  plc.reads = plc.waits = 0;
  One(move, plc, 1.7);
  EXPECT_EQ(plc.reads, 3);
  EXPECT_EQ(plc.waits, 2);
}

TEST(AcknowledgedMove, RefusesBeforeSendingWhenNotActiveOrBlindOrMiscounted) {
  FakePlc plc(1);
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  std::array<Measurement, 1> out;
  const std::array<double, 1> c{1.0};
  const std::array<double, 2> two{1.0, 2.0};
  EXPECT_THROW(move.Move(c, out, plc, false, ""), TransferError);
  try {
    move.Move(c, out, plc, true, "the link is down");
    ADD_FAILURE();
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("command 1 mm not sent: the actuator's position could "
                                         "not be read before moving (the link is down)"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(move.Move(two, out, plc, true, ""), TransferError);
  EXPECT_EQ(plc.writes, 0);
  EXPECT_EQ(plc.holds, 0) << "nothing was sent: nothing to hold";
}

TEST(AcknowledgedMove, AMissingAckTimesOutHoldsAndRefusesUntilStarted) {
  FakePlc plc(1);
  plc.silent = true;
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  const std::string error = Failure(move, plc, 1.0);
  EXPECT_NE(error.find("the fake PLC did not acknowledge within 0.05 s while waiting for the ack "
                       "of command 1 mm (sequence 1)"), std::string::npos) << error;
  EXPECT_NE(error.find("the fake holds"), std::string::npos) << error;
  EXPECT_EQ(plc.holds, 1);
  // Even a protocol that still says "active" is refused until Start().
  plc.silent = false;
  EXPECT_NE(Failure(move, plc, 1.0).find("not active"), std::string::npos);
  EXPECT_EQ(plc.writes, 1);
  move.Start(std::vector<std::uint64_t>{0});
  EXPECT_EQ(One(move, plc, 1.0).position, 1.0);
}

TEST(AcknowledgedMove, AnAckFromAnotherClientHolds) {
  FakePlc plc(1);
  plc.other_client = true;
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{6});
  const std::string error = Failure(move, plc, 1.0);
  EXPECT_NE(error.find("acknowledged sequence 42, expected 7 (or the previous 6 while moving)"),
            std::string::npos) << error;
  EXPECT_NE(error.find("another client"), std::string::npos) << error;
  EXPECT_EQ(plc.holds, 1);
}

TEST(AcknowledgedMove, AFaultADroppedEnableOrHoldingStopsAndHolds) {
  for (int flag = 0; flag < 3; ++flag) {
    FakePlc plc(2);
    plc.state[1].fault = flag == 0;
    plc.state[1].enabled = flag != 1;
    plc.state[1].holding = flag == 2;
    AcknowledgedMove move = MoveOf(2);
    move.Start(std::vector<std::uint64_t>{0, 0});
    std::array<Measurement, 2> out;
    const std::array<double, 2> c{1.0, 2.0};
    std::string error;
    try {
      move.Move(c, out, plc, true, "");
    } catch (const TransferError& e) {
      error = e.what();
    }
    const char* expected[] = {"the fake PLC: actuator 2 reports a fault (bit F)",
                              "the fake PLC: actuator 2 dropped the enable (bit E)",
                              "the fake PLC: actuator 2 reports holding (bit H)"};
    EXPECT_NE(error.find(expected[flag]), std::string::npos) << error;
    EXPECT_NE(error.find("(sequence [1, 1])"), std::string::npos) << error;
    EXPECT_EQ(plc.holds, 1) << error;
  }
}

TEST(AcknowledgedMove, OnlyTheFirstExchangeIsCheckedForPlausibility) {
  FakePlc plc(1);
  plc.state[0].force = std::numeric_limits<double>::quiet_NaN();
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  std::string error = Failure(move, plc, 1.0);
  EXPECT_NE(error.find("implausible first measurement from the fake PLC: command 1 mm"),
            std::string::npos) << error;
  EXPECT_NE(error.find("|force| ≤ 1000000 N; the fake holds; check the fake's scale"),
            std::string::npos) << error;
  EXPECT_EQ(plc.holds, 1);
  // After Start(): a plausible first exchange, then a force beyond 1 MN passes (the runner's
  // force limits judge it, not this check).
  plc.state[0].force = 0.0;
  move.Start(std::vector<std::uint64_t>{1});
  One(move, plc, 1.0);
  plc.state[0].force = 2e6;
  EXPECT_EQ(One(move, plc, 1.1).force, 2e6);
  // A first position 2 mm off the command is implausible.
  plc.offset[0] = 2.0;
  move.Start(std::vector<std::uint64_t>{2});
  error = Failure(move, plc, 1.0);
  EXPECT_NE(error.find("expected the position within 1 mm of the command"), std::string::npos)
      << error;
}

TEST(AcknowledgedMove, AFollowingErrorIsASafetyStopInMetresAfterAHold) {
  FakePlc plc(1);
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  One(move, plc, 1.0);
  plc.offset[0] = 0.5;  // mm: beyond the default 0.2 mm
  const SafetyStop stop = StopOf(move, plc, 1.5);
  EXPECT_EQ(stop.limit(), "following_error");
  EXPECT_NEAR(stop.value(), 0.5e-3, 1e-12);        // [m]
  EXPECT_NEAR(stop.limit_value(), 0.2e-3, 1e-12);  // [m]
  const std::string what = stop.what();
  EXPECT_NE(what.find("The fake PLC acknowledged command 1.5 mm (sequence 2) but measured "
                      "position 2 mm"), std::string::npos) << what;
  EXPECT_NE(what.find("the fake holds"), std::string::npos) << what;
  EXPECT_EQ(plc.holds, 1);
  EXPECT_NE(Failure(move, plc, 1.5).find("not active"), std::string::npos);
}

TEST(AcknowledgedMove, AStaleAckIsASafetyStopInMetresAfterAHold) {
  FakePlc plc(1);
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  One(move, plc, 1.0);
  // Acknowledged with the previous position, bit for bit, after a 0.15 mm move (> 2 × 0.05).
  plc.stale = true;
  const SafetyStop stop = StopOf(move, plc, 1.15);
  EXPECT_EQ(stop.limit(), "stale_acknowledgement");
  EXPECT_NEAR(stop.value(), 0.15e-3, 1e-12);       // [m]
  EXPECT_NEAR(stop.limit_value(), 0.1e-3, 1e-12);  // [m]
  EXPECT_EQ(plc.holds, 1);
}

TEST(AcknowledgedMove, WhatTheProtocolThrowsPassesUnchangedAfterAHold) {
  FakePlc plc(1);
  AcknowledgedMove move = MoveOf(1);
  move.Start(std::vector<std::uint64_t>{0});
  plc.refuse_write = true;
  EXPECT_EQ(Failure(move, plc, 1.0), "the fake refused the write");
  EXPECT_EQ(plc.holds, 1);
  plc.refuse_write = false;
  plc.fail_read = true;
  move.Start(std::vector<std::uint64_t>{0});
  EXPECT_EQ(Failure(move, plc, 1.0), "the fake lost the link");
  EXPECT_EQ(plc.holds, 2);
}

TEST(AcknowledgedMove, ASharedStatusNamesTheController) {
  FakePlc plc(2);
  plc.state[0].fault = plc.state[1].fault = true;
  ControllerOptions o;
  AcknowledgedMove move(o, Millimetres(), {65536, 65536}, true, "fake transfer");
  move.Start(std::vector<std::uint64_t>{0, 0});
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{1.0, 2.0};
  try {
    move.Move(c, out, plc, true, "");
    ADD_FAILURE();
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("the fake PLC reports a fault (bit F)"),
              std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hybridtest::transfer
