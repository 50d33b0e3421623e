// See site_journal.h.
#include "hybridtest/transfer/site/site_journal.h"

#include <fmt/core.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"

namespace hybridtest::transfer::site {
namespace {

std::string JournalIdFields(const TransactionId& id) {
  return fmt::format("{} {} {} {} {}", id.run, id.seq, id.step, id.stage, id.attempt);
}

double ParseJournalFloat(const std::string& word, const std::string& where) {
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (end == word.c_str() || *end != '\0') {
    throw ConfigError(fmt::format("{}: '{}' is not a number", where, word));
  }
  return v;
}

}  // namespace

SiteJournal::SiteJournal(const std::string& path, std::uintmax_t max_bytes)
    : path_(path), max_bytes_(max_bytes) {
  if (path.empty()) return;
  // The executes already recorded: their keys are applied at most once.
  std::ifstream in(path);
  std::string line;
  long number = 0;
  while (in && std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind != "execute") continue;
    const std::string where = fmt::format("{}:{}", path, number);
    TransactionId id;
    std::size_t n = 0;
    if (!(words >> id.run >> id.seq >> id.step >> id.stage >> id.attempt >> n) || n == 0 ||
        n > 1024) {
      throw ConfigError(fmt::format("{}: an execute line that cannot be read; the journal is "
                                    "append-only: restore it or start the site on a new file",
                                    where));
    }
    std::vector<Measurement> measured(n);
    for (auto& m : measured) {
      std::string p, f, l, r;
      if (!(words >> p >> f >> l >> r)) {
        throw ConfigError(fmt::format("{}: an execute line with fewer than {} measurements",
                                      where, n));
      }
      m = {ParseJournalFloat(p, where), ParseJournalFloat(f, where), ParseJournalFloat(l, where),
           static_cast<long>(ParseJournalFloat(r, where))};
    }
    Remember(id, std::move(measured));
    ++executes_;
  }
  file_ = std::fopen(path.c_str(), "a");
  if (file_ == nullptr) {
    throw ConfigError(fmt::format("site journal {}: cannot open it for appending; give a "
                                  "writable path with `journal:`", path));
  }
  std::error_code size_error;
  const std::uintmax_t size = std::filesystem::file_size(path, size_error);
  bytes_ = size_error ? 0 : size;
  if (number == 0) Write("# hybridtest site journal v1");
}

SiteJournal::~SiteJournal() {
  if (file_ != nullptr) std::fclose(file_);
}

bool SiteJournal::HasRoom(std::size_t n) const {
  // The longest lines: a run tag of 64 bytes, five numbers of ≤ 20 digits, the verdict (a
  // limit name), n hexadecimal floats (≤ 25 bytes each) per target, 4 n per execute.
  const std::uintmax_t id = 8 + kMaxRunTagBytes + 5 * 21;
  const std::uintmax_t propose = id + 64 + 26 * n;
  const std::uintmax_t execute = id + 6 + 4 * 26 * n;
  const std::uintmax_t hold = 6 + kHoldWhyBytes + 1;
  const std::uintmax_t need = propose + execute + 2 * hold;
  return bytes_ <= max_bytes_ && max_bytes_ - bytes_ >= need;
}

void SiteJournal::Write(const std::string& line) {
  bytes_ += line.size() + 1;
  if (file_ == nullptr) return;
  std::fputs(line.c_str(), file_);
  std::fputc('\n', file_);
  std::fflush(file_);
}

void SiteJournal::Proposed(const Proposal& p, const std::string& verdict) {
  std::string line = fmt::format("propose {} {}", JournalIdFields(p.id), verdict);
  for (double t : p.targets) line += fmt::format(" {:a}", t);
  Write(line);
}

void SiteJournal::Executed(const TransactionId& id, const std::vector<Measurement>& measured) {
  std::string line = fmt::format("execute {} {}", JournalIdFields(id), measured.size());
  for (const auto& m : measured) {
    line += fmt::format(" {:a} {:a} {:a} {:a}", m.position, m.force, m.lab_time,
                        static_cast<double>(m.force_reversals));
  }
  Write(line);
  Remember(id, measured);
  ++executes_;
}

void SiteJournal::Held(const std::string& why) {
  const std::string line = "hold " + Printable(why).substr(0, kHoldWhyBytes);
  if (bytes_ + line.size() + 1 > max_bytes_) return;  // full: the site refuses proposals
  Write(line);
}

const std::vector<Measurement>* SiteJournal::Find(const TransactionId& id) const {
  const auto it = done_.find({id.run, id.seq});
  return it == done_.end() ? nullptr : &it->second;
}

void SiteJournal::Remember(const TransactionId& id, std::vector<Measurement> measured) {
  auto key = std::make_pair(id.run, id.seq);
  if (done_.emplace(key, std::move(measured)).second) order_.push_back(std::move(key));
  while (order_.size() > kRemembered) {
    done_.erase(order_.front());
    order_.pop_front();
  }
}

}  // namespace hybridtest::transfer::site
