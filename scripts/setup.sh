#!/usr/bin/env bash
# Install, only when missing, the Debian packages freestand builds and tests with.
# Idempotent: a machine that already has everything makes no network request.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  liggghts libliggghts-dev liggghts-doc
  libopenmpi-dev openmpi-bin
  libeigen3-dev libhdf5-dev hdf5-tools libvtk9-dev libqhull-dev
  libboost-dev  # Boost.Math (header only): Student t and normal quantiles of the diagnose statistics
  libgtest-dev libgmock-dev libbenchmark-dev
  libnlopt-cxx-dev libliquid-dev libcli11-dev nlohmann-json3-dev libfmt-dev zlib1g-dev
  libmujoco-dev  # used only by bench/ (MuJoCo 2.2.2, the peer in bench/time_to_accuracy.sh)
  python3-h5py python3-numpy
  paraview xvfb xauth x11-utils chromium
)

# pvpython renders the ParaView series (postprocess/render_frame.py). Debian 12's
# python3-paraview conflicts with python3-vtk9, which libvtk9-dev depends on, so
# it is unpacked (never installed) into this prefix; pvpython finds its Python
# modules next to itself. Same version as the installed paraview package.
PVPYTHON_PREFIX=/opt/freestand/python3-paraview

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
else
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if command -v pvpython >/dev/null || [ -x "$PVPYTHON_PREFIX/usr/bin/pvpython" ]; then
  echo "setup: pvpython present"
else
  version=$(dpkg-query -W -f='${Version}' paraview)
  echo "setup: unpacking python3-paraview $version into $PVPYTHON_PREFIX"
  download=$(mktemp -d)
  (cd "$download" && apt-get download -qq "python3-paraview=$version")
  $SUDO rm -rf "$PVPYTHON_PREFIX.part"
  $SUDO mkdir -p "$(dirname "$PVPYTHON_PREFIX")"
  $SUDO dpkg-deb -x "$download"/python3-paraview_*.deb "$PVPYTHON_PREFIX.part"
  $SUDO mv "$PVPYTHON_PREFIX.part" "$PVPYTHON_PREFIX"
  rm -rf "$download"
fi
