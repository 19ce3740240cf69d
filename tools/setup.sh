#!/usr/bin/env bash
# Check (and if possible install) the system packages wavetrace needs to build and test:
#   libvulkan1           the Vulkan loader (ash loads libvulkan.so.1 at run time)
#   mesa-vulkan-drivers  lavapipe, the CPU Vulkan driver tests run on without a GPU
#   glslang-tools        glslangValidator, which build.rs runs to compile shaders
#   spirv-tools          spirv-opt, which specializes kernels before pipeline creation
#                        (src/gpu/specialize.rs; without it start-up is seconds slower)
# Idempotent and quiet when everything is present. Missing packages are installed with
# apt-get when running as root (or with sudo when it works without a password);
# otherwise the exact command to run is printed and the script exits with status 1.
set -euo pipefail

missing=()

# The loader: ask the dynamic linker's cache first, then the usual places.
if ! { ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; } \
    && ! ls /usr/lib/*/libvulkan.so.1 /usr/lib/libvulkan.so.1 >/dev/null 2>&1; then
    missing+=(libvulkan1)
fi

# lavapipe's ICD manifest (lvp_icd.<arch>.json).
if ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
    missing+=(mesa-vulkan-drivers)
fi

if ! command -v glslangValidator >/dev/null 2>&1; then
    missing+=(glslang-tools)
fi

if ! command -v spirv-opt >/dev/null 2>&1; then
    missing+=(spirv-tools)
fi

if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi

install="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
echo "setup.sh: missing ${missing[*]}" >&2

if ! command -v apt-get >/dev/null 2>&1; then
    echo "setup.sh: no apt-get here; install the Vulkan loader, Mesa's lavapipe driver" \
        "glslangValidator and spirv-opt with your package manager" >&2
    exit 1
fi

if [ "$(id -u)" -eq 0 ]; then
    sudo_cmd=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo_cmd=(sudo)
else
    echo "setup.sh: run as root:  $install" >&2
    exit 1
fi

echo "setup.sh: installing: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
