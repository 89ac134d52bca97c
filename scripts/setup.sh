#!/usr/bin/env bash
# Install, only when missing, the Debian packages freestand builds and tests with.
# Idempotent: a machine that already has everything makes no network request.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  liggghts libliggghts-dev liggghts-doc
  libopenmpi-dev openmpi-bin
  libeigen3-dev libhdf5-dev hdf5-tools libvtk9-dev libqhull-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libnlopt-cxx-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libmujoco-dev  # used only by bench/ (MuJoCo 2.2.2, the peer in bench/time_to_accuracy.sh)
  python3-h5py python3-numpy
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
