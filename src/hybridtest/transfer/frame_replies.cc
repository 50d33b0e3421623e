// See frame_replies.h.
#include "hybridtest/transfer/frame_replies.h"

#include <fmt/core.h>

namespace hybridtest::transfer {

bool SendFrameOn(ServerLoop& loop, ServerLoop::Connection& c, const Frame& frame) {
  return loop.Send(c, EncodeFrame(frame));
}

void SendErrorOn(ServerLoop& loop, ServerLoop::Connection& c, std::uint32_t sequence,
                 ErrorMessage m, const std::function<void(const std::string&)>& log) {
  if (m.text.size() > kMaxErrorTextBytes) m.text.resize(kMaxErrorTextBytes);
  if (log) {
    log(fmt::format("ERROR {} (sequence {}): {}",
                    ErrorCodeName(static_cast<std::uint16_t>(m.code)), sequence, m.text));
  }
  SendFrameOn(loop, c, EncodeError(sequence, m));
}

}  // namespace hybridtest::transfer
