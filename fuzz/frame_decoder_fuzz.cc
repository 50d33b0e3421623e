// libFuzzer target: the bench protocol's frame decoder and message decoders (frame.h,
// protocol.h), the bytes a network peer controls. Any input must either decode or raise a
// TransferError; a crash, a sanitizer report or another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <span>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/protocol.h"

using namespace hybridtest::transfer;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  try {
    if (size >= kFrameHeaderSize) (void)DecodeFrameHeader(bytes.first(kFrameHeaderSize));
  } catch (const hybridtest::TransferError&) {
  }
  Frame frame;
  try {
    frame = DecodeFrame(bytes);
  } catch (const hybridtest::TransferError&) {
    // Also try the payload decoders on a frame whose header and CRC we fix up, so that the
    // fuzzer reaches them without having to forge a CRC.
    if (size < 2) return 0;
    frame.type = static_cast<MessageType>(1 + data[0] % 10);
    frame.sequence = data[1];
    frame.payload.assign(data + 2, data + size);
    if (frame.payload.size() > kMaxPayloadLength) return 0;
  }
  try {
    switch (frame.type) {
      case MessageType::kHello: (void)DecodeHello(frame); break;
      case MessageType::kWelcome: (void)DecodeWelcome(frame); break;
      case MessageType::kCommand: (void)DecodeCommands(frame); break;
      case MessageType::kMeasurement: (void)DecodeMeasurements(frame, 1); break;
      case MessageType::kError: (void)DecodeError(frame); break;
      default: DecodeEmpty(frame, frame.type); break;
    }
    // Whatever decodes must encode again.
    (void)EncodeFrame(frame);
  } catch (const hybridtest::TransferError&) {
  }
  return 0;
}
