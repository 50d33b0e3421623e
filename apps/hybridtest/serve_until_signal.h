#pragma once
// Serving until SIGINT or SIGTERM, for the commands that run a server (`hybridtest bench`,
// `hybridtest site`): the handler only calls the served server's Stop(), which stores an
// atomic flag; Serve() then returns within its poll interval.
#include <csignal>

namespace hybridtest::app {

// The server of type `Server` being served (at most one per type at a time).
template <typename Server>
Server*& ServedServer() {
  static Server* served = nullptr;
  return served;
}

template <typename Server>
void StopServedServer(int /*signal*/) {
  if (Server* s = ServedServer<Server>(); s != nullptr) s->Stop();
}

// Calls server.Serve() with SIGINT and SIGTERM asking it to stop; the registration is cleared
// when Serve() returns or throws.
template <typename Server>
void ServeUntilSignal(Server& server) {
  ServedServer<Server>() = &server;
  struct sigaction action {};
  action.sa_handler = StopServedServer<Server>;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  try {
    server.Serve();
  } catch (...) {
    ServedServer<Server>() = nullptr;
    throw;
  }
  ServedServer<Server>() = nullptr;
}

}  // namespace hybridtest::app
