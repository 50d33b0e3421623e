#pragma once
// The answers of every server of the bench protocol's frames on the one ServerLoop
// (BenchServer, the multi-site SiteServer): a frame, and an ERROR whose text is cut to
// kMaxErrorTextBytes and logged. One place, so that both servers answer alike.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/protocol.h"
#include "hybridtest/transfer/server_loop.h"

namespace hybridtest::transfer {

inline constexpr std::size_t kMaxErrorTextBytes = 4000;  // an ERROR's text, cut. [bytes]

// Sends `frame` on `c`; false if the connection is to end (ServerLoop::Send).
bool SendFrameOn(ServerLoop& loop, ServerLoop::Connection& c, const Frame& frame);

// Logs "ERROR CODE (sequence N): TEXT" through `log` and sends ERROR `m` answering
// `sequence`, its text cut to kMaxErrorTextBytes.
void SendErrorOn(ServerLoop& loop, ServerLoop::Connection& c, std::uint32_t sequence,
                 ErrorMessage m, const std::function<void(const std::string&)>& log);

}  // namespace hybridtest::transfer
