#!/usr/bin/env bash
# Runs a representative part of the test suite under the Khronos validation layer
# (WAVETRACE_VALIDATION=1: src/gpu/validation.rs; synchronization validation on; the
# first validation error aborts the process, so a test binary with one fails).
# First proves the layer is live: examples/validation_probe makes one forbidden call
# and must abort with the layer's message. Used by .ci/run; needs
# vulkan-validationlayers (tools/setup.sh).
#
#   tools/validation.sh            the CI part (a few minutes on two cores)
#   tools/validation.sh --test X   any other cargo test arguments instead
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

cargo build -q --example validation_probe
probe_out=$(mktemp)
if WAVETRACE_VALIDATION=1 target/debug/examples/validation_probe >"$probe_out" 2>&1; then
    cat "$probe_out"
    echo "validation.sh: the probe's forbidden call was not caught: the layer is not active" >&2
    exit 1
fi
if ! grep -q "Vulkan validation error: .*VUID-VkBufferCreateInfo-size-00912" "$probe_out"; then
    cat "$probe_out"
    echo "validation.sh: the probe failed, but not with the layer's report" >&2
    exit 1
fi
echo "validation.sh: the layer is active (the probe's forbidden call aborted)"

if [ $# -gt 0 ]; then
    WAVETRACE_VALIDATION=1 cargo test "$@"
    exit
fi
# Every kernel family once: path tracing, MIS, textures and normal maps over Mitsuba's
# regression scenes; emitters; GPU records; texture lookups; grid media; progressive
# rendering; one photon-mapping render (photon emission, grid, gather).
WAVETRACE_VALIDATION=1 cargo test --test mitsuba_regression_suite --test render \
    --test emitters --test records --test texture_lookups_gpu_vs_cpu --test media_grids \
    --test progressive --test letterbox --test viewer
WAVETRACE_VALIDATION=1 cargo test --test photon photon_mapper_estimates_irradiance_under_a_point_light
