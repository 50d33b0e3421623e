// See site_config.h.
#include "hybridtest/io/site_config.h"

#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/physical_slot_config.h"
#include "hybridtest/io/transfer_readers.h"

namespace hybridtest::io {

SiteConfig LoadSiteConfig(const std::string& path) {
  const YamlInput in = YamlInput::FromFile(path, "a `site:` mapping");
  const YAML::Node root = in.root();
  in.CheckKeys(root, "", {"site"});
  const YAML::Node site = in.Mapping(root, "site", "site", true);
  in.CheckKeys(site, "site", {"name", "transfer", "safety", "start_position", "watchdog",
                              "journal", "journal_max_mb", "refusals_per_minute"});
  SiteConfig c;
  auto& o = c.server;
  if (site["name"]) o.name = in.String(site["name"], "site.name", "a name");
  try {
    transfer::site::CheckRunTag(o.name);
  } catch (const TransferError&) {
    in.ThrowValue(site["name"], "site.name", "1 to 64 letters, digits, '-', '_' or '.'");
  }
  const transfer::SafetyLimits limits = internal::ParseSafety(in, site["safety"], "site.safety");
  o.limits = {limits};
  const YAML::Node tr = in.Mapping(site, "transfer", "site.transfer", true);
  c.transfer = ReadTransfer({in, tr, "site.transfer", std::nullopt, limits.timeout, &limits});
  if (const YAML::Node n = site["start_position"]) {
    o.start_positions = {in.Number(n, "site.start_position", "a position in m")};
  }
  if (const YAML::Node n = site["watchdog"]) {
    o.watchdog = in.PositiveNumber(n, "site.watchdog", "a time in seconds");
  }
  if (const YAML::Node n = site["journal_max_mb"]) {
    o.journal_max_bytes = static_cast<std::uintmax_t>(
        in.Count(n, "site.journal_max_mb", "the journal's size bound in MiB", 1, 1 << 24))
        << 20;
  }
  if (const YAML::Node n = site["refusals_per_minute"]) {
    o.refusals_per_minute = static_cast<std::size_t>(in.Count(
        n, "site.refusals_per_minute", "refused proposals journaled per minute", 1, 1000000));
  }
  if (const YAML::Node n = site["journal"]) {
    std::filesystem::path file = in.String(n, "site.journal", "the path of the journal file");
    if (file.is_relative()) file = std::filesystem::path(path).parent_path() / file;
    o.journal = file.string();
  } else {
    throw ConfigError(fmt::format("{}: give `journal: FILE`, the site's append-only record of "
                                  "its transactions", in.Where(site, "site")));
  }
  return c;
}

}  // namespace hybridtest::io
