#!/usr/bin/env bash
# Installs the Debian packages hairlod builds, tests and runs with. Idempotent: apt-get runs only
# when something is missing. Nothing comes from PyPI.
set -euo pipefail

packages=(
  build-essential cmake pkg-config patchelf debootstrap
  libglm-dev libtbb-dev libembree-dev libosd-dev libopenexr-dev libeigen3-dev libnanoflann-dev
  pybind11-dev python3-pybind11 python3-dev python3-numpy python3-pytest python3-setuptools python3-pip
  python3-matplotlib python3-skimage python3-openimageio
  libgtest-dev libbenchmark-dev
  blender xvfb xauth
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "bootstrap: installing ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "bootstrap: missing packages (${missing[*]}) and no root or sudo to install them" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q "${missing[@]}"
