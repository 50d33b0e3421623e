#!/bin/sh
# Installs the test peer's npm packages (ads-client) into node_modules/ beside this script,
# pinned by package.json; does nothing when they are installed. Run by the ADS peer tests,
# which CTest may start at the same time: `npm ci` first deletes node_modules/, so two at once
# break each other. The first takes the lock and installs; the others wait for it and then
# find the packages installed. The marker is written only after a complete install, so an
# install that was killed half-way is done again.
set -eu
cd "$(dirname "$0")"
exec 9>.install.lock
flock 9
if [ -f node_modules/.hybridtest-installed ]; then exit 0; fi
npm ci --no-audit --no-fund --loglevel=error
touch node_modules/.hybridtest-installed
