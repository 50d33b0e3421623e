#!/bin/sh
# Installs the test peer's npm packages (ads-client) into node_modules/ beside this script,
# pinned by package.json; does nothing when they are installed. Run by the ADS peer test.
set -eu
cd "$(dirname "$0")"
if [ -f node_modules/ads-client/package.json ]; then exit 0; fi
exec npm ci --no-audit --no-fund --loglevel=error
