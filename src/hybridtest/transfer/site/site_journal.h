#pragma once
// SiteJournal: a site's append-only record of its transactions (docs/multi-site.md), one line
// per event, flushed as it is written:
//
//   # hybridtest site journal v1
//   propose RUN SEQ STEP STAGE ATTEMPT accept|refuse:LIMIT T1 ... Tn
//   execute RUN SEQ STEP STAGE ATTEMPT N P1 F1 L1 R1 ... Pn Fn Ln Rn
//   hold WHY...
//
// targets and measurements in the bench's units, as hexadecimal floats (bit for bit). The
// executed transactions are also remembered (the most recent kRemembered), so a site answers a
// repeated EXECUTE of a key (RUN, SEQ) from the record: an id is applied at most once, also
// across a restart of the site on the same journal (Open() reads the file's executes back).
//
// Size bound: the file never grows past `max_bytes` (its size when opened counts). The site
// asks HasRoom(n) before it writes a proposal of n targets; it reserves room for that
// proposal's line, its execute's and two hold lines (WHY cut to kHoldWhyBytes), so an execute
// of an accepted proposal is always written (nothing committed is lost).
#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/transfer/site/site_protocol.h"

namespace hybridtest::transfer::site {

class SiteJournal {
 public:
  static constexpr std::size_t kRemembered = 100000;  // executed keys kept in memory
  static constexpr std::size_t kHoldWhyBytes = 200;   // a hold line's WHY, cut. Unit: [bytes].
  static constexpr std::uintmax_t kUnbounded = UINTMAX_MAX;

  // Opens (creates) `path` for appending and reads back the executes already in it; an empty
  // path keeps the record in memory only (its bytes are counted all the same). Throws
  // ConfigError naming the file if it cannot be opened or a line cannot be read.
  explicit SiteJournal(const std::string& path, std::uintmax_t max_bytes = kUnbounded);
  ~SiteJournal();
  SiteJournal(const SiteJournal&) = delete;
  SiteJournal& operator=(const SiteJournal&) = delete;

  void Proposed(const Proposal& p, const std::string& verdict);  // "accept" | "refuse:LIMIT"
  void Executed(const TransactionId& id, const std::vector<Measurement>& measured);
  void Held(const std::string& why);
  // The measurements recorded for `id`'s key, if it was executed.
  const std::vector<Measurement>* Find(const TransactionId& id) const;
  long executes() const { return executes_; }  // lines written or read back
  // True if a proposal of `n` targets, its execute and two holds fit under max_bytes.
  bool HasRoom(std::size_t n) const;
  std::uintmax_t bytes() const { return bytes_; }          // the file's size. Unit: [bytes].
  std::uintmax_t max_bytes() const { return max_bytes_; }  // Unit: [bytes].

 private:
  void Write(const std::string& line);
  void Remember(const TransactionId& id, std::vector<Measurement> measured);
  std::FILE* file_ = nullptr;
  std::string path_;
  std::map<std::pair<std::string, std::uint32_t>, std::vector<Measurement>> done_;
  std::deque<std::pair<std::string, std::uint32_t>> order_;
  long executes_ = 0;
  std::uintmax_t bytes_ = 0, max_bytes_ = kUnbounded;
};

}  // namespace hybridtest::transfer::site
