#!/usr/bin/env bash
# Installs, with apt-get, the Debian 12 packages that hybridtest needs. Does nothing when they
# are all present already. Run as root (or with sudo available).
#   scripts/install-deps.sh           everything: build, run, test, benchmark, fuzz and plot
#   scripts/install-deps.sh --app     only what building and running the hybridtest binary needs
#                                     (the main job: compiler, libraries, gnuplot)
#   scripts/install-deps.sh --docs    also a headless browser, to render the HTML report to a PNG
#                                     for the documentation (docs/results-format.md)
#   scripts/install-deps.sh --print   print the packages of the chosen set and install nothing
set -euo pipefail

app_packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev zlib1g-dev libssl-dev
  libhdf5-dev hdf5-tools
  libmodbus-dev libcpp-httplib-dev   # cpp-httplib: the HTTP client of the monitor's tests
  libzip-dev libpugixml-dev          # FMUs: unpacking them, reading modelDescription.xml
  libginac-dev                       # the Symbolic scalar (`equations`)
  gnuplot-nox
)
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-sympy python3-yaml python3-h5py python3-numpy
  python3-pymodbus python3-serial python3-serial-asyncio   # the Modbus test controller
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-pytest                  # the Python package and its tests
  libopenmpi-dev openmpi-bin                               # campaigns on a cluster (MPI)
  chromium                                                 # the monitor's page test
  nodejs                                                   # the monitor page's axis test (node)
  texlive-latex-base                                       # pdflatex: `equations --format latex` test
)

app_only=0
print_only=0
docs=0
for arg in "$@"; do
  case "$arg" in
    --app) app_only=1 ;;
    --print) print_only=1 ;;
    --docs) docs=1 ;;
    *) echo "install-deps.sh: unknown option '$arg'; expected --app, --docs or --print" >&2; exit 2 ;;
  esac
done
packages=("${app_packages[@]}")
if ((app_only == 0)); then
  packages+=("${test_packages[@]}")
fi
if ((docs)); then
  packages+=(chromium-headless-shell)
fi
# npm fetches uPlot for the monitor's page at build time (docs/monitor.md), and ads-client, the
# independent ADS client the tests run against the TwinCAT PLC emulator (tests/transfer/ads/peer/;
# Debian's npm brings nodejs); a node install that brings its own npm is enough.
if ((app_only == 0)) && ! command -v npm >/dev/null; then
  packages+=(npm)
fi
if ((print_only)); then
  echo "${packages[*]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "hybridtest: installing Debian packages: ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "hybridtest: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
