// See lock_free_observer.h.
#include "hybridtest/runner/lock_free_observer.h"

#include <fmt/core.h>

#include <algorithm>

#include "hybridtest/common/error.h"

namespace hybridtest::runner {

LockFreeObserver::LockFreeObserver(SessionObserver& inner, std::size_t capacity,
                                   std::size_t row_size, std::chrono::microseconds poll)
    : inner_(inner),
      ring_(std::max<std::size_t>(capacity, 1),
            [row_size] {
              Slot s;
              s.x.resize(row_size);
              s.r.resize(row_size);
              s.row.resize(row_size);
              return s;
            }),
      poll_(poll) {}

LockFreeObserver::~LockFreeObserver() { Stop(); }

void LockFreeObserver::OnStart(const Session& session) {
  inner_.OnStart(session);
  running_ = true;
  consumer_ = std::thread([this] { Consume(); });
}

void LockFreeObserver::OnCommit(const CommitEvent& e) {
  {
    const std::lock_guard<std::mutex> lock(error_mutex_);  // uncontended: the consumer takes
    if (error_) std::rethrow_exception(error_);            // it only to store a failure
  }
  Slot* s = ring_.Claim();
  if (s == nullptr) {
    throw Error(fmt::format("the observers' queue is full ({} rows): the files cannot keep up "
                            "with the real-time loop; the test is stopped safely. Raise "
                            "real_time.queue or write to a faster disk", ring_.capacity()));
  }
  if (e.x.size() > s->x.size() || e.r.size() > s->r.size() || e.row.size() > s->row.size()) {
    throw Error("LockFreeObserver: a row longer than the row size it was made for");
  }
  s->kind = e.kind;
  s->step = e.step;
  s->t = e.t;
  s->nx = e.x.size();
  s->nr = e.r.size();
  s->nrow = e.row.size();
  std::copy(e.x.begin(), e.x.end(), s->x.begin());
  std::copy(e.r.begin(), e.r.end(), s->r.begin());
  std::copy(e.row.begin(), e.row.end(), s->row.begin());
  ring_.Publish();
}

void LockFreeObserver::Consume() {
  while (true) {
    Slot* s = ring_.Front();
    if (s == nullptr) {
      if (!running_.load()) return;
      std::this_thread::sleep_for(poll_);
      continue;
    }
    try {
      const CommitEvent e{s->kind, s->step, s->t, {s->x.data(), s->nx}, {s->r.data(), s->nr},
                          {s->row.data(), s->nrow}};
      inner_.OnCommit(e);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    ring_.Pop();
    ++delivered_;
  }
}

void LockFreeObserver::Drain() {
  while (!ring_.empty() && consumer_.joinable()) std::this_thread::sleep_for(poll_);
}

void LockFreeObserver::Stop() {
  if (!consumer_.joinable()) return;
  Drain();
  running_ = false;
  consumer_.join();
}

void LockFreeObserver::OnStop(const StopEvent& event) {
  Stop();
  inner_.OnStop(event);
}

}  // namespace hybridtest::runner
