#pragma once
// The byte layout of OpenFresco's generic TCP protocol, mode A: a client (OpenSees's
// `expElement genericClient`, OpenFresco's ECGenericTCP control or its plain-C client) talking
// to a SimApp element/site server. Implemented from the protocol's published facts (see
// docs/openfresco.md); no OpenFresco code is used.
//
//   connection = header, then messages, both ways, until the client sends action 99 or leaves
//   header     = 11 × int32: sizeCtrl[5] (disp, vel, accel, force, time),
//                sizeDaq[5] (the same order), dataSize
//   message    = exactly dataSize × float64, zero-padded; word 0 of a client message is the
//                action (Action below); replies carry no action word
//
// Both numbers are in the machine's native byte order; hybridtest speaks little-endian (x86,
// ARM) and says so at compile time. OpenSees sends {n,n,n,0,1, 0,0,0,n,0, max(256, 3n+2, n²)};
// OpenFresco's plain-C client sends a time size of 0 ({n,n,n,0,0, 0,0,0,n,0, 256}). Both are
// accepted.
//
// Replies: getForce (10) → the n forces in words 0..n−1; getInitialStiff, getTangentStiff,
// getDamp, getMass (12–15) → an n × n matrix in column-major order; getDaqResponse (6) →
// disp | vel | accel | force | time, block sizes sizeDaq. Actions 3 (trial response),
// 5 (commit) and 99 (die) have no reply.
//
// hybridtest extension (not OpenFresco): a server with a shared token expects the token
// before the header, as int32 kTokenMagic, int32 L (1 ≤ L ≤ kMaxTokenBytes), L bytes. The
// magic word can never be a valid sizeCtrl[0], so a server tells both openings apart.
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hybridtest::transfer::openfresco {

static_assert(std::endian::native == std::endian::little,
              "the OpenFresco wire format is native-endian; hybridtest implements little-endian");

// The action codes of word 0 of a client message.
enum class Action : int {
  kOpen = 1,
  kSetup = 2,
  kSetTrialResponse = 3,
  kExecute = 4,
  kCommitState = 5,
  kGetDaqResponse = 6,
  kGetDisp = 7,
  kGetVel = 8,
  kGetAccel = 9,
  kGetForce = 10,
  kGetTime = 11,
  kGetInitialStiff = 12,
  kGetTangentStiff = 13,
  kGetDamp = 14,
  kGetMass = 15,
  kShutdown = 98,
  kDie = 99,
};

// "getForce" for 10, "unknown" for codes outside the protocol.
std::string ActionName(int action);

// Response kinds of sizeCtrl and sizeDaq, by index.
enum SizeIndex { kDisp = 0, kVel = 1, kAccel = 2, kForce = 3, kTime = 4 };

constexpr std::size_t kHeaderBytes = 11 * 4;
constexpr int kDefaultDataSize = 256;   // OF_Network_dataSize
constexpr int kMaxDofs = 1024;          // largest size this implementation accepts
constexpr int kMaxDataSize = 1 << 20;   // largest dataSize accepted (8 MiB messages)
constexpr std::int32_t kTokenMagic = 0x4B4F5448;  // bytes "HTOK"
constexpr int kMaxTokenBytes = 4096;

struct Header {
  std::array<std::int32_t, 5> size_ctrl{};  // disp, vel, accel, force, time
  std::array<std::int32_t, 5> size_daq{};   // the same order
  std::int32_t data_size = 0;               // float64 words per message

  int dofs() const { return size_ctrl[kDisp]; }  // n, the element's degrees of freedom
  bool operator==(const Header&) const = default;
};

// The plain-C client's header for n degrees of freedom: {n,n,n,0,0, 0,0,0,n,0, dataSize}
// with dataSize = max(256, 3n+2, n²).
Header PlainHeader(int n);

std::vector<std::uint8_t> EncodeHeader(const Header& header);
// Decodes 44 bytes without judging them. Throws TransferError for another length.
Header DecodeHeader(std::span<const std::uint8_t> bytes);

// Throws TransferError unless the header can be served: every size in [0, kMaxDofs], n ≥ 1,
// dataSize in [1, kMaxDataSize] and large enough for the longest message of the session
// (1 + Σ sizeCtrl, n², Σ sizeDaq). The message names the offending field and its value.
void ValidateHeader(const Header& header);

// `values` zero-padded to `data_size` words. Throws TransferError if they do not fit.
std::vector<std::uint8_t> EncodeMessage(std::span<const double> values, int data_size);
// 8·k bytes → k float64 values. Throws TransferError for a length not a multiple of 8.
std::vector<double> DecodeMessage(std::span<const std::uint8_t> bytes);

// The action in word 0 of a client message: its integer value, or −1 when word 0 is not a
// whole number in [0, 1000] (NaN, 3.5, 1e300, ...).
int ActionOf(std::span<const double> message);

// The token preamble of the hybridtest extension (see above). Throws TransferError for an
// empty token or one longer than kMaxTokenBytes.
std::vector<std::uint8_t> EncodeTokenPreamble(const std::string& token);

// A client's opening: the optional token preamble, then the 44-byte header.
struct Opening {
  bool has_token = false;  // a token preamble came first
  std::string token;       // its token (empty without a preamble)
  Header header;           // not yet validated (ValidateHeader)
};

// The total number of bytes of the opening that begins with `bytes` (which may be incomplete):
// 4 until the first word is known, then 44 (no preamble) or 8 + L + 44 once L is known. A
// server reads that many bytes without blocking (ServerLoop::Measure). Throws
// TransferError for a preamble length outside 1..kMaxTokenBytes.
std::size_t OpeningSize(std::span<const std::uint8_t> bytes);

// Decodes a complete opening: OpeningSize(bytes) == bytes.size(). Throws TransferError
// otherwise (and for a bad preamble length). The header is not validated.
Opening DecodeOpening(std::span<const std::uint8_t> bytes);

}  // namespace hybridtest::transfer::openfresco
