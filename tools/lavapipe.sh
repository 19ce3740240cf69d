#!/usr/bin/env bash
# Build a newer lavapipe (Mesa's software Vulkan driver) into a cache folder, as an opt-in
# alternative to the Mesa that Debian 12 ships (22.3.6). Nothing calls this script: the
# default driver, the tests and CI stay on the system's lavapipe.
#
#   tools/lavapipe.sh            build (first run) or reuse (later runs), then print the recipe
#   tools/lavapipe.sh --env      print only `export VK_ICD_FILENAMES=...` (for eval)
#   tools/lavapipe.sh --prebuilt no build: Debian's own binary lavapipe from MESA_SUITE and the
#                                libraries it needs (its libc included), run through a wrapper
#
# What it does:
#   1. installs the build dependencies with apt-get (Debian's LLVM 19, bison, flex, ...) and
#      a meson new enough for Mesa (pip, in a venv under the cache folder);
#   2. gets Mesa's upstream source: with `apt-get source` from a Debian suite that carries a
#      recent Mesa (default: sid; apt checks the signatures and the checksums), or from
#      MESA_SOURCE (a source folder or an upstream tarball) on machines without access to
#      Debian's source packages; a tarball given with MESA_SHA256 is checked against it;
#   3. if the system's glslangValidator is older than Mesa needs (12.2, for lavapipe's
#      acceleration-structure build shaders), runs trixie's glslang-tools under trixie's own
#      libc from a private folder (a build-time tool only: the driver itself links against the
#      system's libraries);
#   4. builds only lavapipe (no GL, EGL, GBM, X11 or Wayland), release, against Debian's
#      LLVM 19, and installs it with its ICD manifest into $CACHE/lavapipe-<version>.
#
# With --prebuilt (where Debian's source packages cannot be reached but its binary ones can,
# or to skip the build): downloads the suite's mesa-vulkan-drivers and every package it
# depends on (apt checks the signed index and each package's checksum), unpacks them into
# $CACHE/lavapipe-deb-<version>/root, and writes bin/with-lavapipe there: it runs a program
# (an ELF binary, e.g. target/release/wavetrace) under that root's dynamic loader, so the
# program and the driver run on the suite's libc and libraries (the driver needs a newer libc
# than Debian 12's); the processes it starts (spirv-opt) run on the system's.
#
# Environment:
#   WAVETRACE_CACHE  cache folder (default ~/.cache/wavetrace)
#   MESA_SUITE       Debian suite to take Mesa's source (or --prebuilt: its binary) from
#                    (default sid)
#   MESA_REFRESH=1   --prebuilt: look for a newer package than the one unpacked
#   MESA_VERSION     Debian source version to take (default: the suite's newest; not with
#                    --prebuilt, which takes the suite's current package)
#   MESA_SOURCE      local Mesa source folder or tarball instead of apt-get source
#   MESA_SHA256      expected sha256 of the MESA_SOURCE tarball
#   JOBS             build jobs (default 2)
#   KEEP_BUILD=1     keep the build folder (about 1 GB) after installing
set -euo pipefail

CACHE=${WAVETRACE_CACHE:-$HOME/.cache/wavetrace}
TOOLS=$CACHE/lavapipe-tools
JOBS=${JOBS:-2}
SUITE=${MESA_SUITE:-sid}
LLVM_MAJOR=19
GLSLANG_MIN=12.2

say() { echo "lavapipe.sh: $*" >&2; }
die() {
    say "error: $*"
    exit 1
}

# The manifest of the newest finished install in the cache, if any.
installed_manifest() {
    local f found=()
    for f in "$CACHE"/lavapipe-[0-9]*/share/vulkan/icd.d/lvp_icd.*.json; do
        [ -f "${f%/share/vulkan/icd.d/*}/.complete" ] && found+=("$f")
    done
    [ ${#found[@]} -gt 0 ] || return 1
    printf '%s\n' "${found[@]}" | sort -V | tail -n 1
}

print_recipe() {
    local manifest=$1 prefix
    if [ "${MODE:-}" = env ]; then
        echo "export VK_ICD_FILENAMES=$manifest"
        return
    fi
    prefix=${manifest%/share/vulkan/icd.d/*}
    cat <<EOF

lavapipe from Mesa ${prefix##*/lavapipe-} is installed in $prefix.
Use it for one command ('wavetrace devices' and render's 'device:' line name the LLVM it runs on):

  VK_ICD_FILENAMES=$manifest wavetrace devices
  VK_ICD_FILENAMES=$manifest wavetrace render scenes/cbox/cbox_path.xml --spp 64 -o cbox.exr

or for the shell: eval "\$(tools/lavapipe.sh --env)"
EOF
}

MODE=build
case "${1:-}" in
--env) MODE="env" ;;
--prebuilt) MODE="prebuilt" ;;
"") ;;
-h | --help)
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'
    exit 0
    ;;
*) die "unknown argument '$1' (try --help)" ;;
esac

if [ "$MODE" != prebuilt ] && [ -z "${MESA_SOURCE:-}" ] && [ -z "${MESA_VERSION:-}" ]; then
    if manifest=$(installed_manifest); then
        say "reusing ${manifest%/share/vulkan/icd.d/*}"
        print_recipe "$manifest"
        exit 0
    fi
fi
[ "$MODE" = env ] && die "no lavapipe built yet: run tools/lavapipe.sh first"

SUDO=
if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null || die "apt-get needs root: run as root or install sudo"
    SUDO=sudo
fi
mkdir -p "$CACHE" "$TOOLS"

# A private apt configuration for one Debian suite (lists and downloads under $TOOLS/apt-$1),
# so that packages of other suites can be downloaded, signature-checked, without touching the
# system's sources. The mirror is the one the system's apt already uses.
# shellcheck disable=SC2016 # apt's own $(...) fields, not the shell's
MIRROR=${MESA_DEBIAN_MIRROR:-$(apt-get indextargets --format '$(REPO_URI) $(LABEL)' | awk '$2 == "Debian" { print $1; exit }')}
[ -n "$MIRROR" ] || die "no Debian mirror in apt's sources; set MESA_DEBIAN_MIRROR"
suite_apt() { # suite, deb or deb-src, apt-get or apt-cache, its arguments...
    local suite=$1 kind=$2 dir=$TOOLS/apt-$1
    shift 2
    mkdir -p "$dir/lists/partial" "$dir/cache/archives/partial"
    echo "$kind [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $MIRROR $suite main" >"$dir/sources.list"
    "$1" -qq -o Dir::Etc::sourcelist="$dir/sources.list" -o Dir::Etc::sourceparts=- \
        -o Dir::State::Lists="$dir/lists" -o Dir::Cache="$dir/cache" \
        -o Dir::State::status=/var/lib/dpkg/status -o APT::Sandbox::User=root "${@:2}"
}
# Downloads packages of a suite (the caller has updated its lists) into folder DEBS and unpacks
# them into folder ROOT (both made afresh): suite, debs, root, packages...
unpack_debs() {
    local suite=$1 debs=$2 root=$3 deb
    shift 3
    rm -rf "$debs" "$root"
    mkdir -p "$debs" "$root"
    (cd "$debs" && suite_apt "$suite" deb apt-get download "$@") ||
        die "could not download packages of Debian $suite: $*"
    for deb in "$debs"/*.deb; do dpkg-deb -x "$deb" "$root"; done
}

# --- --prebuilt: Debian's binary lavapipe and its libraries, under their own loader ---------
if [ "$MODE" = prebuilt ]; then
    # The newest finished unpacking is reused as it is (MESA_REFRESH=1 looks for a newer
    # package); its folder is named by the package's version.
    PREFIX=$(for f in "$CACHE"/lavapipe-deb-*/.complete; do
        if [ -f "$f" ]; then echo "${f%/.complete}"; fi
    done | sort -V | tail -n 1)
    ver=${PREFIX##*/lavapipe-deb-}
    if [ -z "$PREFIX" ] || [ "${MESA_REFRESH:-0}" = 1 ]; then
        say "looking up mesa-vulkan-drivers in Debian $SUITE"
        suite_apt "$SUITE" deb apt-get update
        ver=$(suite_apt "$SUITE" deb apt-cache show mesa-vulkan-drivers | awk '/^Version:/ { print $2; exit }')
        [ -n "$ver" ] || die "Debian $SUITE has no package mesa-vulkan-drivers"
        PREFIX=$CACHE/lavapipe-deb-${ver#*:}
    fi
    if [ ! -f "$PREFIX/.complete" ]; then
        # The package and every package it depends on, recursively (libraries: the suite's
        # libc, LLVM, libdrm, the X and Wayland client libraries the driver links).
        pkgs=$(suite_apt "$SUITE" deb apt-cache depends --recurse --no-recommends --no-suggests \
            --no-conflicts --no-breaks --no-replaces --no-enhances mesa-vulkan-drivers |
            grep -v '^[ <]' | sort -u)
        say "downloading $(echo "$pkgs" | wc -l) packages of Debian $SUITE (mesa-vulkan-drivers $ver)"
        rm -rf "$PREFIX"
        # shellcheck disable=SC2086 # one package name per word
        unpack_debs "$SUITE" "$PREFIX/debs" "$PREFIX/root" $pkgs
        rm -rf "$PREFIX/debs"
        mkdir -p "$PREFIX/bin"
        lib=$PREFIX/root/usr/lib/x86_64-linux-gnu
        if [ ! -f "$lib/libvulkan_lvp.so" ] || [ ! -x "$lib/ld-linux-x86-64.so.2" ]; then
            die "the unpacked packages have no libvulkan_lvp.so or dynamic loader in $lib"
        fi
        # The package's GPU drivers (about 120 MB) and the documentation are not needed.
        find "$lib" -maxdepth 1 -name 'libvulkan_*.so' ! -name libvulkan_lvp.so -delete
        rm -rf "$PREFIX/root/usr/share/doc" "$PREFIX/root/usr/share/man"
        cat >"$PREFIX/lvp_icd.json" <<EOF
{
    "ICD": {
        "api_version": "1.3.0",
        "library_path": "$lib/libvulkan_lvp.so"
    },
    "file_format_version": "1.0.0"
}
EOF
        cat >"$PREFIX/bin/with-lavapipe" <<EOF
#!/bin/sh
# Runs an ELF program (the first argument) with lavapipe from Debian $SUITE's Mesa $ver, under
# the dynamic loader and libraries of $PREFIX/root (tools/lavapipe.sh --prebuilt).
[ \$# -ge 1 ] || { echo "usage: \$0 PROGRAM [ARGS...]" >&2; exit 2; }
prog=\$(command -v "\$1") || { echo "\$0: no program \$1" >&2; exit 127; }
shift
VK_ICD_FILENAMES="$PREFIX/lvp_icd.json" exec "$lib/ld-linux-x86-64.so.2" --library-path "$lib" "\$prog" "\$@"
EOF
        chmod +x "$PREFIX/bin/with-lavapipe"
        touch "$PREFIX/.complete"
    else
        say "reusing $PREFIX"
    fi
    cat <<EOF

lavapipe from Debian $SUITE's Mesa $ver is unpacked in $PREFIX.
Run a wavetrace binary with it ('wavetrace devices' and render's 'device:' line name the LLVM it
runs on; VK_ICD_FILENAMES alone does not do: the driver needs the libc it was built for):

  $PREFIX/bin/with-lavapipe target/release/wavetrace devices
  $PREFIX/bin/with-lavapipe target/release/wavetrace render scenes/cbox/cbox_path.xml --spp 64 -o cbox.exr

or let wavetrace measure it against the system's driver, at 256 and 512 bits, and use the
fastest from then on without the wrapper (docs/usage.md, "driver"):

  target/release/wavetrace driver --calibrate
EOF
    exit 0
fi

# --- 1. build dependencies -----------------------------------------------------------------
say "installing build dependencies (apt-get)"
$SUDO apt-get update -qq
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "llvm-$LLVM_MAJOR-dev" bison flex pkgconf python3-venv ninja-build glslang-tools \
    libdrm-dev libzstd-dev zlib1g-dev libexpat1-dev xz-utils ca-certificates dpkg-dev >/dev/null
if [ ! -x "$TOOLS/venv/bin/meson" ]; then
    say "installing meson, mako and pyyaml into $TOOLS/venv (pip)"
    python3 -m venv "$TOOLS/venv"
    "$TOOLS/venv/bin/pip" install -q 'meson>=1.4,<2' mako pyyaml packaging
fi
# Mesa's meson probes python3.16 ... python3.10 by name; pyenv's shims answer for versions
# that are not installed and then fail, so they stay off the build's PATH (the venv's python
# has mako and yaml anyway).
PATH=$(echo "$PATH" | tr ':' '\n' | grep -v '/\.pyenv/' | paste -sd:)
export PATH="$TOOLS/bin:$TOOLS/venv/bin:/usr/lib/llvm-$LLVM_MAJOR/bin:$PATH"

# --- 2. Mesa's source ------------------------------------------------------------------------
SRC_ROOT=$CACHE/lavapipe-src
mkdir -p "$SRC_ROOT"
if [ -n "${MESA_SOURCE:-}" ]; then
    if [ -d "$MESA_SOURCE" ]; then
        SRC=$(cd "$MESA_SOURCE" && pwd)
    elif [ -f "$MESA_SOURCE" ]; then
        if [ -n "${MESA_SHA256:-}" ]; then
            echo "$MESA_SHA256  $MESA_SOURCE" | sha256sum --check --quiet ||
                die "$MESA_SOURCE does not have the sha256 MESA_SHA256 gives"
        fi
        SRC=$SRC_ROOT/$(basename "$MESA_SOURCE" | sed 's/\.tar\..*$//; s/\.orig$//; s/_/-/')
        if [ ! -f "$SRC/VERSION" ]; then
            mkdir -p "$SRC"
            tar -xf "$MESA_SOURCE" -C "$SRC" --strip-components=1
        fi
    else
        die "MESA_SOURCE=$MESA_SOURCE is neither a folder nor a file"
    fi
else
    say "looking up Mesa's source in Debian $SUITE"
    suite_apt "$SUITE" deb-src apt-get update
    ver=
    for v in $(suite_apt "$SUITE" deb-src apt-cache showsrc mesa | awk '/^Version:/ { print $2 }'); do
        if [ -n "${MESA_VERSION:-}" ]; then
            [ "$v" = "$MESA_VERSION" ] && ver=$v
        elif [ -z "$ver" ] || dpkg --compare-versions "$v" gt "$ver"; then
            ver=$v
        fi
    done
    [ -n "$ver" ] || die "Debian $SUITE has no source package mesa${MESA_VERSION:+ $MESA_VERSION}"
    upstream=${ver#*:}
    upstream=${upstream%-*}
    SRC=$SRC_ROOT/mesa-$upstream
    if [ ! -f "$SRC/VERSION" ]; then
        # apt-get source checks the signed Sources index and the .dsc's checksums.
        (cd "$SRC_ROOT" && suite_apt "$SUITE" deb-src apt-get source --download-only "mesa=$ver") ||
            die "could not download Mesa $ver's source from Debian $SUITE; on a machine without
  Debian's source packages give MESA_SOURCE=<Mesa source folder or tarball> (and MESA_SHA256)"
        mkdir -p "$SRC"
        tar -xf "$SRC_ROOT/mesa_$upstream.orig.tar.xz" -C "$SRC" --strip-components=1
    fi
fi
[ -f "$SRC/VERSION" ] || die "$SRC has no VERSION file: not a Mesa source tree"
VERSION=$(cat "$SRC/VERSION")
PREFIX=$CACHE/lavapipe-$VERSION
BUILD=$CACHE/lavapipe-build-$VERSION
if [ -f "$PREFIX/.complete" ] && manifest=$(ls "$PREFIX"/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null); then
    say "reusing $PREFIX"
    print_recipe "$manifest"
    exit 0
fi
say "building lavapipe from Mesa $VERSION ($SRC) into $PREFIX"

# --- 3. glslangValidator >= 12.2 ---------------------------------------------------------
# `glslangValidator --version` says "Glslang Version: 11:12.0.0"; the release is the last field.
glslang_version() { "$1" --version 2>/dev/null | awk -F: '/Glslang Version/ { gsub(/ /, "", $NF); print $NF }' | cut -d. -f1,2; }
version_ge() { [ "$(printf '%s\n%s\n' "$2" "$1" | sort -V | head -n 1)" = "$2" ]; }
sys_glslang=$(glslang_version glslangValidator || true)
if ! version_ge "${sys_glslang:-0}" "$GLSLANG_MIN"; then
    root=$TOOLS/trixie-root
    if [ ! -x "$TOOLS/bin/glslangValidator" ]; then
        say "system glslangValidator is ${sys_glslang:-missing} (< $GLSLANG_MIN): using trixie's, under trixie's libc"
        suite_apt trixie deb apt-get update
        unpack_debs trixie "$TOOLS/debs" "$root" glslang-tools spirv-tools libc6 libstdc++6 libgcc-s1
        mkdir -p "$TOOLS/bin"
        cat >"$TOOLS/bin/glslangValidator" <<EOF
#!/bin/sh
exec "$root/usr/lib/x86_64-linux-gnu/ld-linux-x86-64.so.2" --library-path "$root/usr/lib/x86_64-linux-gnu:$root/lib/x86_64-linux-gnu" "$root/usr/bin/glslangValidator" "\$@"
EOF
        chmod +x "$TOOLS/bin/glslangValidator"
    fi
    got=$(glslang_version "$TOOLS/bin/glslangValidator" || true)
    version_ge "${got:-0}" "$GLSLANG_MIN" || die "trixie's glslangValidator does not run (version '${got}')"
fi

# --- 4. build and install ----------------------------------------------------------------------
options=(
    --prefix="$PREFIX" --libdir=lib -Dbuildtype=release -Db_ndebug=true
    -Dplatforms= -Dvulkan-drivers=swrast -Dgallium-drivers=llvmpipe
    -Dllvm=enabled -Dshared-llvm=enabled -Ddraw-use-llvm=true
    -Dopengl=false -Dgles1=disabled -Dgles2=disabled -Dglx=disabled -Degl=disabled
    -Dgbm=disabled -Dglvnd=disabled -Dgallium-va=disabled -Dgallium-rusticl=false
    -Dvideo-codecs= -Dvulkan-layers= -Dtools= -Dbuild-tests=false -Dteflon=false
    -Dvalgrind=disabled -Dlibunwind=disabled -Dlmsensors=disabled -Dzstd=enabled
    -Dshader-cache=enabled -Dmicrosoft-clc=disabled -Dintel-rt=disabled
    -Dperfetto=false -Dhtml-docs=disabled
)
rm -rf "$PREFIX"
if [ -f "$BUILD/build.ninja" ]; then
    # An interrupted build goes on where it stopped.
    meson setup --reconfigure "$BUILD" "$SRC" "${options[@]}"
else
    rm -rf "$BUILD"
    meson setup "$BUILD" "$SRC" "${options[@]}"
fi
ninja -C "$BUILD" -j "$JOBS"
ninja -C "$BUILD" install >/dev/null
manifest=$(ls "$PREFIX"/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null) || die "the install has no lvp_icd manifest"
grep -q "\"$PREFIX/lib/libvulkan_lvp.so\"" "$manifest" || die "$manifest does not name $PREFIX/lib/libvulkan_lvp.so"
touch "$PREFIX/.complete"
[ "${KEEP_BUILD:-0}" = 1 ] || rm -rf "$BUILD"
print_recipe "$manifest"
