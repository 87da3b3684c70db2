#!/usr/bin/env bash
# Debian chroots for what this machine (Debian 12) cannot show by itself, made with debootstrap once
# per machine and kept in $HAIRLOD_CHROOTS (default /var/cache/hairlod): made again when missing,
# topped up when their package list below changes.
#
#   debian13  Debian 13 (trixie) with the build tools and Blender 4.3 (Python 3.13, Embree 4,
#             TBB 2022, OpenSubdiv 3.6, NumPy 2): the suites on a second platform.
#   sid       Debian unstable with the same packages: Blender 5.2 LTS (Python 3.14, NumPy 2.4,
#             GCC 16, pybind11 3), the Blender 5 line artists run. Unstable moves: it installs what
#             the mirror holds when the chroot is made (apt accepts the mirror's Release file after
#             its Valid-Until, as a mirror snapshot's is).
#   bare12    Debian 12 with only python3 and python3-numpy: where a packaged hairlod must import
#             and work with nothing else installed.
#
#   scripts/chroot.sh NAME setup          make or top up the chroot
#   scripts/chroot.sh NAME run CMD...     run CMD inside it (as root, in /hairlod = this checkout,
#                                         /shared = ../shared when present)
#
# `run` mounts proc, dev, a tmpfs on /tmp and this checkout in a private mount namespace
# (unshare), so the mounts vanish with the command, also when it fails or is killed.
set -euo pipefail

mirror=${HAIRLOD_DEBIAN_MIRROR:-http://deb.debian.org/debian}
checkout=$(cd "$(dirname "$0")/.." && pwd)

die() { echo "chroot.sh: $*" >&2; exit 1; }

name=${1:-}
case "$name" in
  debian13|sid)
    release=$([ "$name" = sid ] && echo sid || echo trixie)
    # What the build, the suites and Blender under Xvfb need (x11-apps: xwd captures the window,
    # since bpy.ops.screen.screenshot returns black there; patchelf: the packages).
    packages=(
      build-essential cmake pkg-config patchelf
      libglm-dev libtbb-dev libembree-dev libosd-dev libopenexr-dev libeigen3-dev libnanoflann-dev
      pybind11-dev python3-dev python3-numpy python3-pytest
      python3-matplotlib python3-skimage python3-openimageio
      libgtest-dev
      blender xvfb xauth x11-apps
    ) ;;
  bare12)
    release=bookworm
    packages=(python3 python3-numpy) ;;
  *) die "usage: scripts/chroot.sh debian13|sid|bare12 setup | run CMD..." ;;
esac
shift
root=${HAIRLOD_CHROOTS:-/var/cache/hairlod}/$name

need_root() {
  [ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot and mounts); run it as root or under sudo"
}

install_host_tools() {
  local missing=()
  command -v debootstrap >/dev/null || missing+=(debootstrap)
  command -v unshare >/dev/null || missing+=(util-linux)
  if [ ${#missing[@]} -gt 0 ]; then
    echo "chroot.sh: installing ${missing[*]} on the host"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
  fi
}

# Runs a command in the chroot with the mounts it needs, in a mount namespace of its own.
in_chroot() {
  local dir=$1; shift
  unshare --mount --propagation private -- /bin/sh -c '
    set -e
    dir=$1; checkout=$2; shift 2
    mount -t proc proc "$dir/proc"
    mount --rbind /dev "$dir/dev"
    mount -t tmpfs tmpfs "$dir/tmp"
    mkdir -p "$dir/hairlod"
    mount --bind "$checkout" "$dir/hairlod"
    # The shared test data beside the checkout (../shared), where the suites look for it.
    if [ -d "$checkout/../shared" ]; then
      mkdir -p "$dir/shared"
      mount --bind "$checkout/../shared" "$dir/shared"
    fi
    cp /etc/resolv.conf "$dir/etc/resolv.conf" 2>/dev/null || true
    exec chroot "$dir" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 \
      TERM="${TERM:-dumb}" /bin/sh -c "cd /hairlod && exec \"\$@\"" sh "$@"
  ' sh "$dir" "$checkout" "$@"
}

package_stamp() { printf '%s\n' "${packages[@]}" | sha256sum | cut -c1-16; }

setup() {
  need_root
  install_host_tools
  local stamp; stamp=$(package_stamp)
  if [ "$(cat "$root/.hairlod-packages" 2>/dev/null)" = "$stamp" ]; then
    return 0
  fi
  if [ ! -f "$root/.hairlod-base" ]; then
    # Made beside its final place and renamed when complete: an interrupted run leaves no chroot
    # that looks finished.
    local partial="$root.partial"
    rm -rf "$partial"
    mkdir -p "$(dirname "$root")"
    echo "chroot.sh: debootstrap $release into $root (about a minute)"
    debootstrap --variant=minbase "$release" "$partial" "$mirror" >"$partial.log" 2>&1 ||
      { tail -n 20 "$partial.log" >&2; die "debootstrap failed (log: $partial.log)"; }
    touch "$partial/.hairlod-base"
    rm -rf "$root"
    mv "$partial" "$root"
    rm -f "$partial.log"
  fi
  echo "chroot.sh: installing ${#packages[@]} packages in the $name chroot"
  in_chroot "$root" /bin/sh -c "export DEBIAN_FRONTEND=noninteractive &&
    apt-get update -q -o Acquire::Check-Valid-Until=false && apt-get install -y -q --no-install-recommends $(printf '%s ' "${packages[@]}") >/tmp/apt.log 2>&1 ||
    { tail -n 30 /tmp/apt.log >&2; exit 1; }; apt-get clean"
  echo "$stamp" >"$root/.hairlod-packages"
}

case "${1:-}" in
  setup) setup ;;
  run)
    shift
    [ $# -gt 0 ] || die "run: give a command"
    need_root
    [ -f "$root/.hairlod-packages" ] || die "no chroot in $root: run 'scripts/chroot.sh $name setup' first"
    in_chroot "$root" "$@"
    ;;
  *) die "usage: scripts/chroot.sh debian13|sid|bare12 setup | run CMD..." ;;
esac
