#!/usr/bin/env bash
# A reproduction of llvmpipe's abort at 512 bits, for a Mesa bug report: lavapipe from
# Debian sid (Mesa 26.2.6, LLVM 22; tools/lavapipe.sh --prebuilt) with
# LP_NATIVE_VECTOR_WIDTH=512 aborts with "*** stack smashing detected ***" inside
# libvulkan_lvp.so when a compute shader stores u64vec2 values made by packUint2x32.
#
#   tools/mesa_int64_store.sh
#
# Builds examples/int64_store.rs (one dispatch of shaders/tests/int64_store.comp, then a
# check of every word it wrote) and runs its four modes at 256 and 512 bits:
#   0  words[i] = u64vec2(packUint2x32(w.xy), packUint2x32(w.zw))   in-order stores
#   1  the same at words[(7 i) mod n]                                a divergent scatter
#   2  uvec4 stores of the same bytes at words32[(7 i) mod n]        the 32-bit control
#   3  words[i] = u64vec2(uint64_t(lo) | uint64_t(hi) << 32, ...)    no packUint2x32
# Seen (2026-12-06, AMD EPYC with AVX-512): every mode correct at 256 bits; at 512 bits
# modes 0 and 1 abort, 2 and 3 are correct. wavetrace's own kernels abort at 512 bits
# even with mode 3's construct, so src/gpu/device.rs runs the 32-bit stores on llvmpipe
# wider than 256 bits (int64_stores_work).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

version=$(ls -d "${XDG_CACHE_HOME:-$HOME/.cache}"/wavetrace/lavapipe-deb-* 2>/dev/null | tail -n 1)
if [ -z "$version" ]; then
    tools/lavapipe.sh --prebuilt >&2
    version=$(ls -d "${XDG_CACHE_HOME:-$HOME/.cache}"/wavetrace/lavapipe-deb-* | tail -n 1)
fi
run=$version/bin/with-lavapipe
cargo build --quiet --example int64_store
example=${CARGO_TARGET_DIR:-target}/debug/examples/int64_store

for bits in 256 512; do
    for mode in 0 1 2 3; do
        out=$(LP_NATIVE_VECTOR_WIDTH=$bits "$run" "$example" "$mode" 2>&1 || true)
        printf '%s bits, mode %s: %s\n' "$bits" "$mode" "$(printf '%s' "$out" | tail -n 1)"
    done
done
