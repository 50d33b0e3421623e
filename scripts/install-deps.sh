#!/usr/bin/env bash
# Installs, with apt-get, every Debian 12 package that hybridtest needs to build, test and plot.
# Does nothing when they are all present already. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev zlib1g-dev libssl-dev
  libhdf5-dev hdf5-tools
  libmodbus-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-sympy python3-yaml python3-h5py python3-numpy
  python3-pymodbus python3-serial python3-serial-asyncio   # the Modbus test controller
  gnuplot-nox
  clang libclang-rt-14-dev
)

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
