#!/usr/bin/env bash
# Stock LAMMPS 4 Feb 2025 (Debian trixie's version), built once per machine.
#
#   bash scripts/lammps-2025.sh            fetch + verify + build (if needed),
#                                          then print KEY=VALUE lines:
#                                            LAMMPS2025_SRC    <tree>  (cmake/ src/ lib/ python/ tools/)
#                                            LAMMPS2025_BUILD  <build dir> (liblammps.so, lmp)
#   bash scripts/lammps-2025.sh --env      only print them (no fetch, no build)
#   bash scripts/lammps-2025.sh --source   fetch + verify + extract only
#
# Source: the upstream tarball of Debian's `lammps` source package
# 20250204+dfsg.1-2 (trixie), fetched with `apt-get source --download-only`
# through a deb-src entry for trixie (no binary packages from trixie), or
# from Debian's pool by its path if apt-get cannot; always checked against
# its sha256 below. Nothing of it enters the git tree: everything lives in
# $HS_CACHE (default ~/.cache/hardsphere), the build dir is keyed by the
# LAMMPS version and the CMake options, and a lock makes clones that set up
# at the same time wait for one build instead of doing two.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

LMP_VERSION=20250204
DEB_VERSION=20250204+dfsg.1-2
ORIG=lammps_20250204+dfsg.1.orig.tar.xz
ORIG_SIZE=132367436
ORIG_SHA256=3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7
POOL_URL="http://deb.debian.org/debian/pool/main/l/lammps/$ORIG"

# What the tests and examples need: MOLECULE (bonds, angles), KSPACE,
# EXTRA-PAIR (mie/cut, gauss/cut, lj/gromacs, ...), EXTRA-FIX, and PLUGIN
# (plugin load). Shared library (plugins, Python), MPI.
CMAKE_OPTS=(
  -D CMAKE_BUILD_TYPE=Release
  -D BUILD_SHARED_LIBS=on
  -D BUILD_MPI=on
  -D BUILD_OMP=off
  -D LAMMPS_SIZES=smallbig
  -D FFT=KISS
  -D WITH_JPEG=off -D WITH_PNG=off -D WITH_FFMPEG=off
  -D DOWNLOAD_POTENTIALS=off
  -D PKG_MOLECULE=on -D PKG_KSPACE=on -D PKG_PLUGIN=on
  -D PKG_EXTRA-PAIR=on -D PKG_EXTRA-FIX=on
)

CACHE="${HS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hardsphere}"
KEY="$( { echo "$LMP_VERSION $ORIG_SHA256"; printf '%s\n' "${CMAKE_OPTS[@]}";
          c++ --version 2>/dev/null | head -n1; } | sha256sum | cut -c1-12)"
SRC="$CACHE/lammps-$LMP_VERSION-src"
BUILD="$CACHE/lammps-$LMP_VERSION-$KEY"

print_env() {
  echo "LAMMPS2025_SRC=$SRC"
  echo "LAMMPS2025_BUILD=$BUILD"
}
MODE="${1:-build}"
if [ "$MODE" = "--env" ]; then print_env; exit 0; fi

log() { echo "lammps-2025: $*" >&2; }

mkdir -p "$CACHE"
exec 9>"$CACHE/.lammps-$LMP_VERSION.lock"
if ! flock -n 9; then
  log "another set-up holds $CACHE/.lammps-$LMP_VERSION.lock; waiting for it"
  flock 9
fi

if [ "$MODE" != "--source" ] && [ -f "$BUILD/.hs-stamp" ] && [ -f "$BUILD/liblammps.so" ] \
   && [ -x "$BUILD/lmp" ]; then
  log "cached build $BUILD ($(cat "$BUILD/.hs-stamp"))"
  print_env
  exit 0
fi

# ---------------------------------------------------------------- source
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

verify() {
  [ -f "$1" ] && [ "$(stat -c %s "$1")" = "$ORIG_SIZE" ] \
    && echo "$ORIG_SHA256  $1" | sha256sum --quiet -c - 2>/dev/null
}

TARBALL="$CACHE/$ORIG"
if [ -d "$SRC/src" ] && [ -f "$SRC/.hs-stamp" ]; then
  log "source tree $SRC present"
else
  if ! verify "$TARBALL"; then
    rm -f "$TARBALL"
    SRCLIST=/etc/apt/sources.list.d/hs-deb-src-trixie.sources
    if [ ! -f "$SRCLIST" ]; then
      log "adding deb-src entry for trixie: $SRCLIST"
      $SUDO tee "$SRCLIST" >/dev/null <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: trixie
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    fi
    DL="$CACHE/dl"
    mkdir -p "$DL"
    if ! apt-cache showsrc "lammps=$DEB_VERSION" 2>/dev/null | grep -q "$ORIG"; then
      $SUDO apt-get update >&2
    fi
    log "apt-get source --download-only lammps=$DEB_VERSION"
    # the .dsc may be missing on a partial mirror: what counts is the
    # tarball and its checksum
    (cd "$DL" && apt-get source --download-only "lammps=$DEB_VERSION" >&2) \
      || log "apt-get source reported an error; checking what it fetched"
    if ! verify "$DL/$ORIG"; then
      log "no verified tarball from apt-get source; fetching $POOL_URL"
      rm -f "$DL/$ORIG"
      curl -fsSL -o "$DL/$ORIG" "$POOL_URL" || wget -q -O "$DL/$ORIG" "$POOL_URL" || true
    fi
    if ! verify "$DL/$ORIG"; then
      log "ERROR: $ORIG missing or its sha256 is not $ORIG_SHA256"
      exit 1
    fi
    mv "$DL/$ORIG" "$TARBALL"
    rm -rf "$DL"
  fi
  log "sha256 of $ORIG verified; extracting into $SRC"
  rm -rf "$SRC" "$SRC.tmp"
  mkdir -p "$SRC.tmp"
  # only what a build needs (examples/, doc/, bench/, potentials/ are 370 MB)
  tar -xJf "$TARBALL" -C "$SRC.tmp" --strip-components=1 --wildcards \
      '*/cmake/*' '*/src/*' '*/lib/*' '*/python/*' '*/tools/*' '*/LICENSE' '*/README'
  echo "$ORIG sha256 $ORIG_SHA256" > "$SRC.tmp/.hs-stamp"
  mv "$SRC.tmp" "$SRC"
fi

if [ "$MODE" = "--source" ]; then print_env; exit 0; fi

# ---------------------------------------------------------------- build
JOBS="${HS_JOBS:-2}"
log "building LAMMPS $LMP_VERSION in $BUILD with -j$JOBS (about 15 min on 2 cores)"
rm -rf "$BUILD"
start=$(date +%s)
cmake -S "$SRC/cmake" -B "$BUILD" "${CMAKE_OPTS[@]}" >&2
cmake --build "$BUILD" -j"$JOBS" >&2
# the Python module of this build: lammps/ beside a link to its liblammps.so
mkdir -p "$BUILD/python"
rm -rf "$BUILD/python/lammps"
cp -r "$SRC/python/lammps" "$BUILD/python/lammps"
ln -sf "$BUILD/liblammps.so" "$BUILD/python/lammps/liblammps.so"
secs=$(( $(date +%s) - start ))
echo "built $(date -u +%Y-%m-%dT%H:%MZ) in ${secs} s with -j$JOBS" > "$BUILD/.hs-stamp"
log "first build took ${secs} s"
print_env
