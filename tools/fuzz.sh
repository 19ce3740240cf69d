#!/usr/bin/env bash
# Coverage-guided fuzzing of every file wavetrace reads (fuzz/README.md): libFuzzer
# through the libfuzzer-sys crate, on the stable toolchain (coverage comes from
# LLVM's sanitizer-coverage pass, which stable rustc runs with -Cpasses; no
# sanitizer, so no nightly). Needs a C++ compiler for libFuzzer (tools/setup.sh).
#
#   tools/fuzz.sh build                  build every target
#   tools/fuzz.sh list                   the targets
#   tools/fuzz.sh run TARGET [ARGS..]    fuzz one target until stopped (or as ARGS
#                                        say: -runs=N, -max_total_time=S, ...); new
#                                        inputs go to fuzz/work/TARGET, crashes to
#                                        fuzz/artifacts/TARGET
#   tools/fuzz.sh ci [SECONDS]           build, then fuzz each target SECONDS
#                                        (default 10) from its corpus; fails on any
#                                        crash, hang, panic or runaway allocation
#   tools/fuzz.sh repro TARGET FILE..    run the target once on each file
#
# Corpus: fuzz/corpus/TARGET (in the repository, small), plus for the scene targets
# the scenes of ../shared/scenes when it is there (read, never copied in).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

targets=(scene_mitsuba scene_nori obj curves ply serialized vol vdb exr png jpeg hdr)
host=$(rustc -vV | sed -n 's/^host: //p')
bin_dir="target/$host/release"

build() {
    # The flags cargo-fuzz passes with `--sanitizer none`: 8-bit edge counters and a
    # PC table (libFuzzer's coverage), comparison tracing (to get past magic numbers
    # and keywords), stack depth; with debug assertions and overflow checks on, so
    # arithmetic that would wrap in release is found too. `--target` keeps the flags
    # off build scripts and proc-macros.
    local flags=(
        -Cpasses=sancov-module
        -Cllvm-args=-sanitizer-coverage-level=4
        -Cllvm-args=-sanitizer-coverage-inline-8bit-counters
        -Cllvm-args=-sanitizer-coverage-pc-table
        -Cllvm-args=-sanitizer-coverage-trace-compares
        -Cllvm-args=-sanitizer-coverage-stack-depth
        -Cdebug-assertions
        -Coverflow-checks
        --cfg fuzzing
    )
    RUSTFLAGS="${flags[*]}" cargo build --release -p wavetrace-fuzz --target "$host" --bins
}

# Seed folders of a target: its corpus, and for scenes the shared suites' XML files
# (linked into a scratch folder: libFuzzer reads folders, and those hold meshes too).
seeds() {
    local t=$1
    echo "fuzz/corpus/$t"
    local dialect=""
    case $t in
        scene_mitsuba) dialect=mitsuba ;;
        scene_nori) dialect=nori ;;
    esac
    if [ -n "$dialect" ] && [ -d "../shared/scenes/$dialect" ]; then
        local d="target/fuzz-seeds/$t"
        rm -rf "$d"
        mkdir -p "$d"
        find "$(cd ../shared/scenes/$dialect && pwd)" -name '*.xml' -size -64k \
            -exec ln -s {} "$d/" \; 2>/dev/null || true
        echo "$d"
    fi
}

# The scratch folders of fuzz processes that have ended (fuzz/src/lib.rs makes one
# per process, named by its id).
clean_scratch() {
    local d
    for d in /dev/shm/wavetrace-fuzz-* "${TMPDIR:-/tmp}"/wavetrace-fuzz-*; do
        [ -d "$d" ] && ! kill -0 "${d##*-}" 2>/dev/null && rm -rf "$d"
    done
    return 0
}

run() {
    local t=$1
    shift
    clean_scratch
    [ -x "$bin_dir/$t" ] || { echo "fuzz.sh: no target '$t' (tools/fuzz.sh build)" >&2; exit 2; }
    mkdir -p "fuzz/work/$t" "fuzz/artifacts/$t"
    # -timeout: a hang; -rss_limit_mb: memory over all (one allocation over 256 MiB
    # aborts at once, fuzz/src/lib.rs); -max_len: scenes and images that still fit
    # the corpus's size.
    # shellcheck disable=SC2046
    "$bin_dir/$t" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
        -artifact_prefix="fuzz/artifacts/$t/" -print_final_stats=1 "$@" \
        "fuzz/work/$t" $(seeds "$t") || { local status=$?; clean_scratch; return $status; }
    clean_scratch
}

case ${1:-} in
    build) build ;;
    list) printf '%s\n' "${targets[@]}" ;;
    run)
        [ $# -ge 2 ] || { echo "usage: tools/fuzz.sh run TARGET [libFuzzer args]" >&2; exit 2; }
        t=$2
        shift 2
        run "$t" "$@"
        ;;
    repro)
        [ $# -ge 3 ] || { echo "usage: tools/fuzz.sh repro TARGET FILE.." >&2; exit 2; }
        t=$2
        shift 2
        "$bin_dir/$t" -timeout=10 -rss_limit_mb=2048 "$@"
        ;;
    ci)
        secs=${2:-10}
        build
        for t in "${targets[@]}"; do
            echo "== fuzz $t (${secs} s)"
            # A fresh work folder: CI checks the corpus in the repository, then
            # explores from it for a bounded time.
            rm -rf "fuzz/work/$t"
            log=$(mktemp)
            status=0
            run "$t" -max_total_time="$secs" >"$log" 2>&1 || status=$?
            # The start, the end and the figures; the whole log when it failed.
            grep -E '^(#[0-9]+[[:space:]]+(INITED|DONE)|stat::)' "$log" || true
            if [ "$status" -ne 0 ]; then
                tail -n 60 "$log"
                echo "fuzz.sh: target $t failed; the input is under fuzz/artifacts/$t" >&2
                exit 1
            fi
            rm -f "$log"
        done
        ;;
    *)
        sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'
        exit 2
        ;;
esac
