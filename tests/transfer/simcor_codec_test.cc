// UI-SimCor's ASCII codec (transfer/site/simcor_codec.h): lines are measured and parsed into
// the site's transaction types; malformed lines are refused naming the field.
#include "hybridtest/transfer/site/simcor_codec.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::site::simcor {
namespace {

std::vector<std::uint8_t> Bytes(const std::string& s) { return {s.begin(), s.end()}; }

Request Parse(const std::string& s) { return ParseLine(Bytes(s)); }

// The message of the TransferError that parsing `s` throws ("" if it does not throw).
std::string RefusalOf(const std::string& s) {
  try {
    Parse(s);
  } catch (const TransferError& e) {
    return e.what();
  }
  return "";
}

TEST(SimcorCodec, MeasuresALineThroughItsLf) {
  EXPECT_EQ(MeasureLine(Bytes("execute\ttrans1\n")), 15u);
  EXPECT_EQ(MeasureLine(Bytes("execute\ttrans1\r\nnext")), 16u);
  EXPECT_EQ(MeasureLine(Bytes("execute\ttra")), 12u);  // incomplete: one more than given
  EXPECT_THROW(MeasureLine(Bytes(std::string("exe\x01", 4))), TransferError);
  EXPECT_THROW(MeasureLine(Bytes(std::string(kMaxLineBytes, 'a'))), TransferError);
  EXPECT_EQ(MeasureLine(Bytes(std::string(kMaxLineBytes - 1, 'a') + "\n")), kMaxLineBytes);
  EXPECT_TRUE(BeginsLine('p'));
  EXPECT_FALSE(BeginsLine('H'));  // a bench-protocol frame
}

TEST(SimcorCodec, ParsesAProposeWithStepsAndSeveralControlPoints) {
  const Request r = Parse("propose\ttrans20240101120000.125[12 1 0]\tMDL-00-01:LBCB1\tx\t"
                          "displacement\t1.5\tMDL-00-01:LBCB2\tx\tdisplacement\t-0.25\r\n");
  EXPECT_EQ(r.command, Command::kPropose);
  EXPECT_EQ(r.echo, "trans20240101120000.125[12 1 0]");
  EXPECT_EQ(r.id.run, "trans20240101120000.125-12-1-0");
  EXPECT_EQ(r.id.seq, 1u);
  EXPECT_EQ(r.id.step, 12);
  EXPECT_EQ(r.id.stage, 1);
  EXPECT_EQ(r.id.attempt, 0);
  ASSERT_EQ(r.targets.size(), 2u);
  EXPECT_DOUBLE_EQ(r.targets[0], 1.5);
  EXPECT_DOUBLE_EQ(r.targets[1], -0.25);
  EXPECT_EQ(r.points[1].address, "MDL-00-01:LBCB2");
  EXPECT_EQ(r.points[1].axis, "x");
  // Without steps the name is the key.
  EXPECT_EQ(Parse("execute\ttrans7\tMDL-00-01:LBCB1\n").id.run, "trans7");
  EXPECT_EQ(Parse("execute\ttrans7\n").id.step, -1);
  // The longest id still makes a key the site's journal takes (a run tag).
  const Request longest = Parse("execute\t" + std::string(30, 'a') +
                                "[1000000000 1000000000 -1]\n");
  EXPECT_NO_THROW(CheckRunTag(longest.id.run)) << longest.id.run;
}

TEST(SimcorCodec, ParsesSessionAndControlPointRequests) {
  EXPECT_EQ(Parse("open-session\tMDL-00-01\tsite\n").command, Command::kOpenSession);
  EXPECT_EQ(Parse("close-session\ttrans9\tMDL\tsite\n").command, Command::kCloseSession);
  const Request dummy = Parse("get-control-point\tdummy\tMDL-00-01:LBCB1\n");
  EXPECT_TRUE(dummy.dummy);
  ASSERT_EQ(dummy.points.size(), 1u);
  EXPECT_EQ(dummy.points[0].address, "MDL-00-01:LBCB1");
  const Request query = Parse("get-control-point\ttrans3[2 0 0]\tMDL-00-01:A\tMDL-00-01:B\n");
  EXPECT_FALSE(query.dummy);
  EXPECT_EQ(query.id.run, "trans3-2-0-0");
  EXPECT_EQ(query.points.size(), 2u);
}

TEST(SimcorCodec, RefusesMalformedLinesNamingTheField) {
  EXPECT_NE(RefusalOf("trigger\ttrans1\n").find("'trigger' is not supported"),
            std::string::npos);
  EXPECT_NE(RefusalOf("execute\n").find("without a transaction id"), std::string::npos);
  EXPECT_NE(RefusalOf("execute\ttrans 1\n").find("field 2"), std::string::npos);
  EXPECT_NE(RefusalOf("execute\t" + std::string(31, 'a') + "\n").find("1 to 30"),
            std::string::npos);
  EXPECT_NE(RefusalOf("execute\ttrans1[1 2]\n").find("three integers"), std::string::npos);
  EXPECT_NE(RefusalOf("execute\ttrans1[1 x 0]\n").find("substep"), std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tx\tdisplacement\t1\n").find("before any address"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tMDL-00-01:A\tx\tdisplacement\tabc\n").find("field 6"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tMDL-00-01:A\tx\tdisplacement\tnan\n").find("finite"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tMDL-00-01:A\tz\trotation\t0.1\n").find("rotation"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tMDL-00-01:A\tq\tdisplacement\t1\n").find("axis"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\tMDL-00-01:A\tx\tdisplacement\n").find("incomplete"),
            std::string::npos);
  EXPECT_NE(RefusalOf("propose\ttrans1\n").find("without a target"), std::string::npos);
  EXPECT_NE(RefusalOf("execute\t\ttrans1\n").find("field 2 is empty"), std::string::npos);
  EXPECT_NE(RefusalOf("get-control-point\tdummy\n").find("without an address"),
            std::string::npos);
  std::string many = "propose\ttrans1\tMDL-00-01:A";
  for (std::size_t k = 0; k <= kMaxValues; ++k) many += "\tx\tdisplacement\t0";
  EXPECT_NE(RefusalOf(many + "\n").find("more than"), std::string::npos);
}

TEST(SimcorCodec, FormatsAnswersUiSimCorCanRead) {
  EXPECT_EQ(FormatOk("trans1[1 0 0]", "executed"), "OK\t0\ttrans1[1 0 0]\texecuted\n");
  // A reason never carries a TAB, a line end or "MDL" (which the reader takes for an address).
  EXPECT_EQ(FormatNotOk("trans1", "limit\tstroke at MDL-00-01\nx"),
            "NOT OK\t0\ttrans1\tlimit stroke at mdl-00-01 x\n");
  const std::vector<PointReading> points = {{{"MDL-00-01:A", "x"}, {1.5, 7.5, 0.0, 0}},
                                            {{"MDL-00-01:A", "y"}, {-2.0, 0.25, 0.0, 0}}};
  EXPECT_EQ(FormatControlPoints("dummy", points),
            "OK\t0\tdummy\tMDL-00-01:A\tx\tdisplacement\t1.5\tx\tforce\t7.5\ty\tdisplacement\t-2"
            "\ty\tforce\t0.25\n");
  EXPECT_EQ(EchoOf(Bytes("execute\ttrans1[1 0 0]\tjunk\n")), "trans1[1 0 0]");
  EXPECT_EQ(EchoOf(Bytes("execute\n")), "error");
}

}  // namespace
}  // namespace hybridtest::transfer::site::simcor
