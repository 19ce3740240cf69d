#!/usr/bin/env bash
# Renders one image over N Slurm tasks: a job array of N `wavetrace render --part I/N`
# tasks and a merge job that runs when all of them have succeeded.
#
#   tools/slurm/submit.sh -n N -o OUT.exr [-d PARTS_DIR] [-s "SBATCH OPTIONS"] \
#       SCENE.xml [wavetrace render options: --spp, --seed, -D, --integrator, ...]
#
# PARTS_DIR (default OUT.parts) must be on a file system every node sees, as must the
# scene and what it names. -s options go to both sbatch calls (e.g. "-p gpu
# --gres=gpu:1 --time=1:00:00"). Prints the two job ids; the image is OUT.exr and
# OUT.png once the merge job is done (`squeue`, `sacct -j ID`).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
usage() {
    sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2
    exit 2
}
parts=""
output=""
parts_dir=""
sbatch_options=""
while getopts "n:o:d:s:h" opt; do
    case $opt in
        n) parts=$OPTARG ;;
        o) output=$OPTARG ;;
        d) parts_dir=$OPTARG ;;
        s) sbatch_options=$OPTARG ;;
        *) usage ;;
    esac
done
shift $((OPTIND - 1))
[ -n "$parts" ] && [ -n "$output" ] && [ $# -ge 1 ] || usage
if ! [[ $parts =~ ^[1-9][0-9]*$ ]]; then
    echo "submit.sh: -n takes a number of parts, not '$parts'" >&2
    exit 2
fi
scene=$(realpath "$1")
shift
output=$(realpath -m "$output")
parts_dir=$(realpath -m "${parts_dir:-${output%.*}.parts}")
mkdir -p "$parts_dir"
# Word splitting of the sbatch options is intended.
# shellcheck disable=SC2086
array=$(sbatch --parsable $sbatch_options --array="0-$((parts - 1))" \
    --chdir="$parts_dir" "$here/render_part.sbatch" "$parts_dir" "$scene" "$@")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable $sbatch_options --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes --chdir="$parts_dir" \
    "$here/merge.sbatch" "$parts_dir" "$output")
merge=${merge%%;*}
echo "render array: job $array ($parts tasks, parts in $parts_dir)"
echo "merge:        job $merge (after all parts succeed) -> $output"
