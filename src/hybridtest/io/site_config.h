#pragma once
// The config of one site of a multi-site test (`hybridtest site --config SITE.yaml`,
// docs/multi-site.md):
//
//   site:
//     name: blade2                  # for logs and messages ([A-Za-z0-9._-])
//     transfer: {type: emulated, config: bench.yaml}   # any transfer type a run config takes
//     safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005,
//              force_soft: 8000, force_hard: 10000, timeout: 5}   # the site's own limits, SI
//     start_position: 0.02          # [m] where the actuators are before the first move
//     watchdog: 5                   # [s] coordinator silence before the bench holds
//     journal: blade2.journal       # the append-only transaction journal (relative path:
//                                   # beside this file)
//     journal_max_mb: 1024          # [MiB] the journal's bound: past it, proposals are refused
//     refusals_per_minute: 600      # refused proposals journaled per minute; beyond: hold
//
// The transfer system is built with the run configs' own reader (transfer_readers.h).
#include <string>

#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/transfer/site/site_server.h"

namespace hybridtest::io {

struct SiteConfig {
  transfer::site::SiteServerOptions server;  // host, port, token and log: the caller's
  substructures::TransferSpec transfer;
};

// Reads SITE.yaml. Throws ConfigError naming file:line, the key and the fix.
SiteConfig LoadSiteConfig(const std::string& path);

}  // namespace hybridtest::io
