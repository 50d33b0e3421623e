// See stop_request.h.
#include "hybridtest/runner/stop_request.h"

#include <atomic>

namespace hybridtest::runner {
namespace {
std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "needed in a signal handler");
}  // namespace

void RequestStop() noexcept { g_stop_requested.store(true, std::memory_order_relaxed); }
bool StopRequested() noexcept { return g_stop_requested.load(std::memory_order_relaxed); }
void ClearStopRequest() noexcept { g_stop_requested.store(false, std::memory_order_relaxed); }

}  // namespace hybridtest::runner
