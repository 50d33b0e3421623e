#pragma once
// The request parser of HttpServer (http_server.h): one HTTP/1.x request from the front of a
// connection's buffer, within the server's limits. Pure: no socket, no allocation beyond the
// request it returns; tested on its own.
#include <cstddef>
#include <string>
#include <string_view>

#include "hybridtest/monitor/http_server.h"

namespace hybridtest::monitor {

enum class ParseStatus {
  kIncomplete,    // wait for more bytes (still within the limits)
  kComplete,      // `request` holds it; `consumed` bytes of the buffer were its
  kBad,           // 400: not an HTTP/1.x request
  kHeadTooLarge,  // 431: more than max_header_bytes or max_headers
  kBodyTooLarge,  // 413: Content-Length over max_body_bytes
  kUnsupported,   // 501: a Transfer-Encoding (chunked bodies are not taken)
};

struct ParseResult {
  ParseStatus status = ParseStatus::kIncomplete;
  std::size_t consumed = 0;
  bool keep_alive = false;
  HttpRequest request;
  std::string why;  // for the client, when refused
};

ParseResult ParseRequest(std::string_view buffer, const HttpLimits& limits);

// `a=1&b=x%20y` → {a: "1", b: "x y"} (+ is a space; a bad escape is kept as it is).
std::map<std::string, std::string> ParseQuery(std::string_view query);

}  // namespace hybridtest::monitor
