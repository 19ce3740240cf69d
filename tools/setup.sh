#!/usr/bin/env bash
# Check (and if possible install) the system packages wavetrace needs to build and test:
#   libvulkan1           the Vulkan loader (ash loads libvulkan.so.1 at run time)
#   mesa-vulkan-drivers  lavapipe, the CPU Vulkan driver tests run on without a GPU
#   glslang-tools        glslangValidator, which build.rs runs to compile shaders
#   spirv-tools          spirv-opt, which specializes kernels before pipeline creation
#                        (src/gpu/specialize.rs; without it start-up is seconds slower)
#   cmake, pkg-config, libx11-dev, libxrandr-dev, libxinerama-dev, libxcursor-dev,
#   libxi-dev            to build the viewer's GLFW from its bundled source (the `glfw`
#                        crate; GLFW loads libX11 at run time, only when `view` opens a
#                        window)
#   xvfb, xdotool        the viewer's tests: a virtual X server and real key presses
#   x11-apps             xwd, with which the viewer's tests read back what the window shows
#   g++                  libFuzzer's C++ runtime, for the fuzz targets .ci/run runs
#                        (tools/fuzz.sh, fuzz/README.md)
#   vulkan-validationlayers  the Khronos validation layer, under which .ci/run runs part
#                        of the suite (tools/validation.sh, WAVETRACE_VALIDATION=1)
# and, for the Slurm test of tools/slurm (tools/slurm/test_slurm.sh, run by .ci/run),
#   slurmctld slurmd slurm-client munge
# which are optional: without root or sudo, their absence is only reported.
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
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
command -v pkg-config >/dev/null 2>&1 || missing+=(pkg-config)
# X11 headers GLFW's X11 backend compiles against, each with its pkg-config file.
for pair in x11:libx11-dev xrandr:libxrandr-dev xinerama:libxinerama-dev \
    xcursor:libxcursor-dev xi:libxi-dev; do
    if ! pkg-config --exists "${pair%%:*}" 2>/dev/null; then
        missing+=("${pair##*:}")
    fi
done
command -v Xvfb >/dev/null 2>&1 || missing+=(xvfb)
command -v xdotool >/dev/null 2>&1 || missing+=(xdotool)
command -v xwd >/dev/null 2>&1 || missing+=(x11-apps)
command -v c++ >/dev/null 2>&1 || missing+=(g++)
if ! ls /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >/dev/null 2>&1; then
    missing+=(vulkan-validationlayers)
fi

# Slurm's controller, node daemon and commands, and munge (its authentication).
optional=()
command -v slurmctld >/dev/null 2>&1 || optional+=(slurmctld)
command -v slurmd >/dev/null 2>&1 || optional+=(slurmd)
command -v sbatch >/dev/null 2>&1 || optional+=(slurm-client)
command -v munged >/dev/null 2>&1 || optional+=(munge)

can_install() {
    command -v apt-get >/dev/null 2>&1 \
        && { [ "$(id -u)" -eq 0 ] || { command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; }; }
}
if [ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -gt 0 ] && ! can_install; then
    echo "setup.sh: note: ${optional[*]} missing (only tools/slurm/test_slurm.sh needs them)" >&2
    optional=()
fi
if [ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ]; then
    exit 0
fi
missing+=("${optional[@]}")

install="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
echo "setup.sh: missing ${missing[*]}" >&2

if ! command -v apt-get >/dev/null 2>&1; then
    echo "setup.sh: no apt-get here; install the Vulkan loader, Mesa's lavapipe driver," \
        "glslangValidator, spirv-opt, cmake, pkg-config, the X11 development headers (X11, Xrandr," \
        "Xinerama, Xcursor, Xi), Xvfb, xdotool, xwd and a C++ compiler with your package manager" >&2
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
