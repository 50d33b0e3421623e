#pragma once
// Untrusted text (config files, their paths, names sent over the network) checked and made safe
// to print: UTF-8 validation (RFC 3629) and escaping of control characters, so that a value
// can neither break a JSON writer nor forge a line in a log.
#include <string>
#include <string_view>

namespace hybridtest {

// The first invalid UTF-8 sequence of `text` as "line L, column C (byte 0xNN)"; empty when
// `text` is valid UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
std::string FindInvalidUtf8(std::string_view text);

// `text` with every control character (U+0000–U+001F, U+007F, so also newlines) and every byte
// that is not part of valid UTF-8 written as \xNN; valid printable UTF-8 is kept as is.
std::string Printable(std::string_view text);

}  // namespace hybridtest
