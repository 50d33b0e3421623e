// See http_parse.h.
#include "hybridtest/monitor/http_parse.h"

#include <algorithm>
#include <cctype>

namespace hybridtest::monitor {
namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool IsTokenChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) ||
         std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

int Hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string Decode(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && i + 2 < s.size() && Hex(s[i + 1]) >= 0 && Hex(s[i + 2]) >= 0) {
      out += static_cast<char>(Hex(s[i + 1]) * 16 + Hex(s[i + 2]));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

ParseResult Refuse(ParseStatus status, std::string why) {
  ParseResult r;
  r.status = status;
  r.why = std::move(why);
  return r;
}

}  // namespace

std::map<std::string, std::string> ParseQuery(std::string_view query) {
  std::map<std::string, std::string> out;
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const std::size_t eq = pair.find('=');
    if (!pair.empty()) {
      out.emplace(Decode(pair.substr(0, eq)),
                  eq == std::string_view::npos ? std::string() : Decode(pair.substr(eq + 1)));
    }
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return out;
}

ParseResult ParseRequest(std::string_view buffer, const HttpLimits& limits) {
  const std::size_t end = buffer.find("\r\n\r\n");
  const std::string_view head = buffer.substr(0, end == std::string_view::npos ? buffer.size() : end);
  // The limits hold before the head is whole: a flood is refused as soon as it passes them.
  const auto lines = static_cast<std::size_t>(std::count(head.begin(), head.end(), '\n'));
  if (head.size() > limits.max_header_bytes) {
    return Refuse(ParseStatus::kHeadTooLarge,
                  "request head over " + std::to_string(limits.max_header_bytes) + " bytes");
  }
  if (lines > limits.max_headers) {
    return Refuse(ParseStatus::kHeadTooLarge,
                  "more than " + std::to_string(limits.max_headers) + " header lines");
  }
  if (end == std::string_view::npos) return {};
  ParseResult r;
  HttpRequest& req = r.request;
  // The request line: METHOD SP TARGET SP HTTP/1.x
  std::size_t at = head.find("\r\n");
  const std::string_view line = head.substr(0, at);
  const std::size_t s1 = line.find(' ');
  const std::size_t s2 = s1 == std::string_view::npos ? s1 : line.find(' ', s1 + 1);
  if (s2 == std::string_view::npos || line.find(' ', s2 + 1) != std::string_view::npos) {
    return Refuse(ParseStatus::kBad, "expected `METHOD /path HTTP/1.1` as the request line");
  }
  req.method = std::string(line.substr(0, s1));
  const std::string_view target = line.substr(s1 + 1, s2 - s1 - 1);
  const std::string_view version = line.substr(s2 + 1);
  if (req.method.empty() || !std::all_of(req.method.begin(), req.method.end(), [](char c) {
        return c >= 'A' && c <= 'Z';
      }) || target.empty() || target.front() != '/' ||
      (version != "HTTP/1.1" && version != "HTTP/1.0")) {
    return Refuse(ParseStatus::kBad, "expected `METHOD /path HTTP/1.1` as the request line");
  }
  const std::size_t q = target.find('?');
  req.path = std::string(target.substr(0, q));
  if (q != std::string_view::npos) req.query = ParseQuery(target.substr(q + 1));
  // The header lines: NAME ":" VALUE
  while (at != std::string_view::npos) {
    const std::size_t next = head.find("\r\n", at + 2);
    const std::string_view h = head.substr(at + 2, next == std::string_view::npos
                                                        ? std::string_view::npos
                                                        : next - at - 2);
    at = next;
    const std::size_t colon = h.find(':');
    if (colon == 0 || colon == std::string_view::npos ||
        !std::all_of(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(colon), IsTokenChar)) {
      return Refuse(ParseStatus::kBad, "a header line is not `Name: value`");
    }
    req.headers.emplace_back(Lower(h.substr(0, colon)), std::string(Trim(h.substr(colon + 1))));
  }
  if (!req.Header("transfer-encoding").empty()) {
    return Refuse(ParseStatus::kUnsupported, "Transfer-Encoding is not taken: send Content-Length");
  }
  std::size_t length = 0;
  if (const std::string cl = req.Header("content-length"); !cl.empty()) {
    if (cl.size() > 18 || !std::all_of(cl.begin(), cl.end(), [](char c) {
          return c >= '0' && c <= '9';
        })) {
      return Refuse(ParseStatus::kBad, "Content-Length is not a number of bytes");
    }
    length = std::stoull(cl);
    if (length > limits.max_body_bytes) {
      return Refuse(ParseStatus::kBodyTooLarge,
                    "body over " + std::to_string(limits.max_body_bytes) + " bytes");
    }
  }
  const std::size_t body_at = end + 4;
  if (buffer.size() < body_at + length) return {};
  req.body = std::string(buffer.substr(body_at, length));
  const std::string connection = Lower(req.Header("connection"));
  r.keep_alive = version == "HTTP/1.1" ? connection != "close" : connection == "keep-alive";
  r.consumed = body_at + length;
  r.status = ParseStatus::kComplete;
  return r;
}

}  // namespace hybridtest::monitor
