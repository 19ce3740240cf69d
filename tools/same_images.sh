#!/usr/bin/env bash
# Renders every shipped scene (scenes/**/*.xml) with two wavetrace binaries and checks
# that the images are the same bit for bit: for a change that must not change what is
# rendered (a refactoring, a reorganized shader tree).
#
#   tools/same_images.sh BEFORE_BINARY AFTER_BINARY [SPP] [OUT_DIR]
#
# Each scene (not the fragments others include) renders at its own resolution (64 x 64 where it has a `res` default),
# SPP samples per pixel (default 2) and seed 7, with its own integrator; the EXRs are
# compared byte for byte (a render is a function of the scene, the seed and the sample
# range alone, so equal kernels give equal files). Prints one line per scene and
# "N same, M differ, K failed"; exit status 1 if any image differs or a render fails.
set -euo pipefail

if [ $# -lt 2 ]; then
    sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
before=$1
after=$2
spp=${3:-2}
out=${4:-$(mktemp -d)}
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mkdir -p "$out/before" "$out/after"

same=0
differ=0
failed=0
while IFS= read -r scene; do
    # Fragments that other scenes include (no camera of their own) are not scenes.
    grep -qE '<(sensor|camera|include)' "$scene" || continue
    name=$(echo "${scene#scenes/}" | tr '/' '_')
    name=${name%.xml}
    args=(render "$scene" --spp "$spp" --seed 7 -q)
    if grep -q 'name="res"' "$scene"; then
        args+=(-D res=64)
    fi
    ok=1
    for side in before after; do
        bin=$before
        [ "$side" = after ] && bin=$after
        if ! "$bin" "${args[@]}" -o "$out/$side/$name.exr" >"$out/$side/$name.log" 2>&1; then
            ok=0
        fi
    done
    if [ $ok = 0 ]; then
        failed=$((failed + 1))
        echo "FAILED  $scene (logs in $out/before/$name.log, $out/after/$name.log)"
    elif cmp -s "$out/before/$name.exr" "$out/after/$name.exr"; then
        same=$((same + 1))
        echo "same    $scene"
    else
        differ=$((differ + 1))
        echo "DIFFER  $scene"
    fi
done < <(find scenes -name '*.xml' | sort)

echo "$same same, $differ differ, $failed failed (images in $out)"
[ $differ = 0 ] && [ $failed = 0 ]
