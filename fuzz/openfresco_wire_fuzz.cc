// libFuzzer target: the OpenFresco server's parsing of what a network peer sends (wire.h): the
// opening (optional token preamble, 44-byte header) as the ServerLoop measures and the
// server decodes it, the header's validation, then messages of dataSize float64 words and
// their action word. Any input must either parse or raise a TransferError; a crash, a
// sanitizer report, another exception, or an opening whose measured size shrinks as its bytes
// arrive (the non-blocking handshake relies on it) is a finding.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/openfresco/wire.h"

using namespace hybridtest::transfer::openfresco;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  // The opening, measured as its bytes arrive one at a time (ServerLoop::Read).
  std::size_t have = 0;
  std::size_t needed = 0;
  try {
    for (;;) {
      const std::size_t now_needed = OpeningSize(bytes.first(have));
      if (now_needed <= have || now_needed < needed) __builtin_trap();  // must grow
      needed = now_needed;
      if (needed > size) return 0;  // the peer would still be sending
      have = needed;
      if (OpeningSize(bytes.first(have)) == have) break;
    }
  } catch (const hybridtest::TransferError&) {
    return 0;
  }
  Header header;
  try {
    const Opening opening = DecodeOpening(bytes.first(have));
    header = opening.header;
    if (EncodeHeader(header) != std::vector<std::uint8_t>(bytes.begin() + static_cast<long>(
                                                              have - kHeaderBytes),
                                                          bytes.begin() + static_cast<long>(have))) {
      __builtin_trap();  // the header must encode back to its bytes
    }
    ValidateHeader(header);
  } catch (const hybridtest::TransferError&) {
    return 0;
  }
  // Messages: the rest, in dataSize × 8-byte pieces (a short last piece is what a server
  // would wait for).
  const std::size_t message_bytes = static_cast<std::size_t>(header.data_size) * 8;
  for (std::size_t at = have; at + message_bytes <= size; at += message_bytes) {
    try {
      const std::vector<double> message = DecodeMessage(bytes.subspan(at, message_bytes));
      const int action = ActionOf(message);
      (void)ActionName(action);
      if (action == static_cast<int>(Action::kSetTrialResponse)) {
        // The trial blocks must fit the message (ValidateHeader's promise).
        std::size_t used = 1;
        for (const std::int32_t s : header.size_ctrl) used += static_cast<std::size_t>(s);
        if (used > message.size()) __builtin_trap();
      }
      (void)EncodeMessage(message, header.data_size);
    } catch (const hybridtest::TransferError&) {
    }
  }
  return 0;
}
