#!/usr/bin/env bash
# HARDSPHERE set-up: install Debian packages, fetch the matching LAMMPS
# headers from Debian's lammps source package, configure and build.
# Idempotent and quick when everything is already in place.
#
# Two LAMMPS versions (HS_LAMMPS_VERSIONS, default "2021 2025"):
#   2021  Debian bookworm's liblammps (29 Sep 2021 update 2)  -> build/
#   2025  stock LAMMPS 4 Feb 2025 (Debian trixie's source), built once per
#         machine under ~/.cache by scripts/lammps-2025.sh (~8-15 min on
#         2 cores the first time)                             -> build-2025/
#         build-2025/lmp, build-2025/hardsphereplugin.so, and
#         build-2025/lammps -> that LAMMPS build (lammps/lmp, lammps/python)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

export DEBIAN_FRONTEND=noninteractive

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

PACKAGES=(lammps liblammps0 liblammps-dev libopenmpi-dev openmpi-bin
          libeigen3-dev googletest libgtest-dev python3-numpy python3-matplotlib
          cmake g++ make dpkg-dev xz-utils ccache)

# ---------------------------------------------------------------- packages
missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
    missing+=("$p")
  fi
done

APT_UPDATED=0
apt_update() {
  if [ "$APT_UPDATED" -eq 0 ]; then
    $SUDO apt-get update
    APT_UPDATED=1
  fi
}

if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing missing packages: ${missing[*]}"
  apt_update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

# ---------------------------------------------------------------- headers
# liblammps-dev ships only a subset of the headers; take the complete set
# (incl. fmt/, neigh_request.h, lammpsplugin.h, version.h) from the matching
# Debian source package. Only headers are kept, in the ignored .cache/ dir.
CACHE="$ROOT/.cache"
HDR="$CACHE/lammps-headers"
STAMP="$HDR/.stamp"
if [ -f "$STAMP" ] && [ -f "$HDR/src/lammps.h" ] && [ -f "$HDR/src/fmt/format.h" ] \
   && [ -f "$HDR/src/lammpsplugin.h" ]; then
  echo "setup: LAMMPS headers present ($(cat "$STAMP"))"
else
  SRCLIST=/etc/apt/sources.list.d/hs-deb-src.sources
  if [ ! -f "$SRCLIST" ]; then
    echo "setup: adding deb-src entry $SRCLIST"
    $SUDO tee "$SRCLIST" >/dev/null <<'SRC'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
    APT_UPDATED=0    # an earlier update in this run did not know deb-src yet
  fi
  # deb-src indices may never have been fetched on this machine
  apt_update
  DL="$CACHE/lammps-src"
  mkdir -p "$DL"
  # exactly the source of the installed library (a deb-src entry for a
  # newer release, e.g. trixie's for scripts/lammps-2025.sh, must not win)
  LIBVER="$(dpkg-query -W -f='${source:Version}' liblammps0)"
  (cd "$DL" && apt-get source --download-only "lammps=$LIBVER")
  tarball="$(ls "$DL"/lammps_*.orig.tar.xz | head -n1)"
  echo "setup: extracting headers from $(basename "$tarball")"
  rm -rf "$HDR"
  mkdir -p "$HDR"
  # strip the top-level lammps-<version>/ directory -> $HDR/src/...
  tar -xJf "$tarball" -C "$HDR" --strip-components=1 \
      --wildcards --no-wildcards-match-slash \
      '*/src/*.h' '*/src/fmt/*' '*/src/PLUGIN/*.h'
  test -f "$HDR/src/lammps.h" && test -f "$HDR/src/fmt/format.h" \
    && test -f "$HDR/src/lammpsplugin.h"
  basename "$tarball" > "$STAMP"
  rm -rf "$DL"
fi

VERSIONS="${HS_LAMMPS_VERSIONS:-2021 2025}"

# ---------------------------------------------------------------- compiler cache
# A fresh clone compiles the package and its ~60 test programs twice (one
# tree per LAMMPS version): most of the set-up's time. ccache keeps the
# objects under ~/.cache/hardsphere/ccache, keyed by preprocessed source and
# flags; CCACHE_BASEDIR makes paths relative to the clone, so a new clone
# anywhere reuses them. HS_CCACHE=0 compiles without it.
LAUNCHER=(-UCMAKE_CXX_COMPILER_LAUNCHER)   # a cached CMake variable: cleared when unused
USE_CCACHE=0
if [ "${HS_CCACHE:-1}" != 0 ]; then
  if command -v ccache >/dev/null; then
    export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/hardsphere/ccache}"
    export CCACHE_BASEDIR="$ROOT"
    export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-3G}"
    LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    USE_CCACHE=1
    ccache --zero-stats >/dev/null
    echo "setup: compiling through ccache ($CCACHE_DIR)"
  else
    echo "setup: ccache not found (package ccache), compiling without it"
  fi
fi

# ---------------------------------------------------------------- build (2021)
if [[ " $VERSIONS " == *" 2021 "* ]]; then
  BUILD="$ROOT/build"
  # always (re)configure: quick, and picks up new style headers / tests
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release "${LAUNCHER[@]}"
  cmake --build "$BUILD" -j2
fi

# ---------------------------------------------------------------- build (2025)
if [[ " $VERSIONS " == *" 2025 "* ]]; then
  eval "$(bash "$ROOT/scripts/lammps-2025.sh")"    # LAMMPS2025_SRC, LAMMPS2025_BUILD
  BUILD25="$ROOT/build-2025"
  mkdir -p "$BUILD25"
  ln -sfn "$LAMMPS2025_BUILD" "$BUILD25/lammps"
  cmake -S "$ROOT" -B "$BUILD25" -DCMAKE_BUILD_TYPE=Release \
    -DLAMMPS_SOURCE_DIR="$LAMMPS2025_SRC/src" \
    -DLAMMPS_LIBRARY="$LAMMPS2025_BUILD/liblammps.so" \
    -DHS_OTHER_PLUGIN="$ROOT/build/hardsphereplugin.so" "${LAUNCHER[@]}"
  cmake --build "$BUILD25" -j2
fi
if [ "$USE_CCACHE" = 1 ]; then
  echo "setup: ccache: $(ccache --print-stats | awk -F'\t' '$1=="direct_cache_hit"||$1=="preprocessed_cache_hit"{h+=$2} $1=="cache_miss"{m=$2} END{printf "%d compiled objects reused, %d compiled", h, m}')"
fi
