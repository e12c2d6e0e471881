#!/usr/bin/env bash
# Submits a tiled render to Slurm: an array of N tile renders, then the merge of the tiles.
#
#   tools/slurm/submit.sh SCENE N OUT [-- LUMIS_RENDER_FLAG...]
#
# SCENE  scene file; N  number of tiles (1..MaxArraySize); OUT  the merged EXR (must end .exr)
# The flags after -- go to every `lumis render` (e.g. -- --width 1920 --height 1080 --spp 2).
# -o, --png and --tile are this script's to set and are refused there.
#
# Prints, on stdout, one line per job and nothing else:
#   array=<job id of the tile array>
#   merge=<job id of the merge>
# Messages go to stderr. The merge waits for afterok of the whole array; if any tile fails, the
# merge is cancelled by Slurm (--kill-on-invalid-dep) rather than left pending forever.
#
# Files: tiles in TILE_DIR (default: OUT without .exr, plus .tiles/), logs in TILE_DIR/logs/
# (render_<I>.log per tile, merge.log).
#
# Environment:
#   LUMIS                the lumis binary (default: `lumis` on PATH, else this checkout's
#                        target/release/lumis)
#   TILE_DIR             where the tiles and logs go (see above)
#   LUMIS_CPUS_PER_TASK  --cpus-per-task of each tile render (default: Slurm's, one CPU);
#                        lumis runs as many threads as the task was given
#   SBATCH_*             sbatch's own input variables (SBATCH_PARTITION, SBATCH_TIMELIMIT,
#                        SBATCH_ACCOUNT, ...) apply to both jobs
#
# SHARED FILE SYSTEM ASSUMED: the scene (and every file it refers to), the lumis binary,
# TILE_DIR and OUT's directory must be visible at the same absolute paths on every node of
# the partition, and on the submitting host. Nothing is staged or copied: the jobs get the
# absolute paths this script resolves, and the merge reads the tiles the array wrote.
set -euo pipefail

usage() {
    echo "usage: submit.sh SCENE N OUT [-- LUMIS_RENDER_FLAG...]" >&2
    exit 2
}
[ "$#" -ge 3 ] || usage
scene_arg=$1
n=$2
out_arg=$3
shift 3
if [ "$#" -gt 0 ]; then
    [ "$1" = "--" ] || usage
    shift
fi
flags=("$@")

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)

if ! [[ "$n" =~ ^[1-9][0-9]*$ ]]; then
    echo "submit.sh: N must be a positive integer, not '$n'" >&2
    exit 2
fi
case $out_arg in
    *.exr) ;;
    *)
        echo "submit.sh: OUT must be an .exr file (tiles and their merge are EXR): $out_arg" >&2
        exit 2
        ;;
esac
for flag in "${flags[@]}"; do
    case $flag in
        -o | --output | --output=* | -o?* | --png | --png=* | --tile | --tile=*)
            echo "submit.sh: $flag is set by the Slurm scripts; remove it from the flags" >&2
            exit 2
            ;;
    esac
done

# Absolute paths: the jobs run in another working directory, on other nodes.
if [ ! -f "$scene_arg" ]; then
    echo "submit.sh: no such scene file: $scene_arg" >&2
    exit 2
fi
scene=$(realpath -- "$scene_arg")
out_dir=$(dirname -- "$out_arg")
if [ ! -d "$out_dir" ]; then
    echo "submit.sh: the directory of OUT does not exist: $out_dir" >&2
    exit 2
fi
out="$(realpath -- "$out_dir")/$(basename -- "$out_arg")"
tile_dir=${TILE_DIR:-${out%.exr}.tiles}
mkdir -p -- "$tile_dir/logs"
tile_dir=$(realpath -- "$tile_dir")

if [ -n "${LUMIS:-}" ]; then
    lumis_cmd=$LUMIS
elif command -v lumis > /dev/null; then
    lumis_cmd=lumis
else
    lumis_cmd=$repo/target/release/lumis
fi
if ! lumis=$(command -v -- "$lumis_cmd") || [ ! -x "$lumis" ]; then
    echo "submit.sh: lumis binary not found or not executable: $lumis_cmd" \
        "(set LUMIS, or cargo build --release)" >&2
    exit 2
fi
lumis=$(realpath -- "$lumis")

array_opts=(--parsable --array="0-$((n - 1))" --output="$tile_dir/logs/render_%a.log")
if [ -n "${LUMIS_CPUS_PER_TASK:-}" ]; then
    array_opts+=(--cpus-per-task="$LUMIS_CPUS_PER_TASK")
fi
# --parsable prints "jobid" or "jobid;cluster": keep the id.
array_id=$(sbatch "${array_opts[@]}" "$here/render_tile.sbatch" \
    "$lumis" "$scene" "$n" "$tile_dir" "${flags[@]}")
array_id=${array_id%%;*}

if ! merge_id=$(sbatch --parsable --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
    --output="$tile_dir/logs/merge.log" "$here/merge.sbatch" "$lumis" "$n" "$tile_dir" "$out")
then
    # An array whose merge never comes would only burn CPU time.
    echo "submit.sh: submitting the merge failed; cancelling the tile array $array_id" >&2
    scancel "$array_id" || true
    exit 1
fi
merge_id=${merge_id%%;*}

echo "submit.sh: $n tiles of $scene -> $out (tiles and logs in $tile_dir)" >&2
echo "array=$array_id"
echo "merge=$merge_id"
