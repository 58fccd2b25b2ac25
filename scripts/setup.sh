#!/usr/bin/env bash
# Installs the Debian 12 packages satf needs; skips what is already there.
# Idempotent; uses sudo when not run as root.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopenvdb-dev libboost-dev libboost-iostreams-dev libtbb-dev
  libopenmesh-dev libopenexr-dev libimath-dev libpng-dev zlib1g-dev
  libglfw3-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  xvfb xauth libcjson-dev libcmocka-dev clang clang-format libclang-rt-dev python3
  libopenmpi-dev openmpi-bin
  blender openimageio-tools python3-openimageio
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: need root or sudo to install: ${missing[*]}" >&2
    exit 1
  fi
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
