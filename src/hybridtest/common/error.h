#pragma once
// The one exception hierarchy of hybridtest. Library code reports every failure by throwing one
// of these; it never terminates the process. Messages follow the house rule: what was
// expected, what was given, where, and how to fix it.
#include <stdexcept>
#include <string>

namespace hybridtest {

// Base of every hybridtest error.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Bad user input: a config file, a CLI argument, a user-supplied Butcher tableau.
class ConfigError : public Error {
 public:
  using Error::Error;
};

// A multibody model that cannot be built or evaluated (bad ids, singular mass matrix, ...).
class ModelError : public Error {
 public:
  using Error::Error;
};

// Communication with a transfer system failed: connection lost, timeout, corrupted frame.
class TransferError : public Error {
 public:
  using Error::Error;
};

// Reading or writing a result file failed.
class IoError : public Error {
 public:
  using Error::Error;
};

}  // namespace hybridtest
