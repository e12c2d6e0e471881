#!/usr/bin/env bash
# What splitting a render into tiles costs: one scene rendered through Slurm as 1, 2, 4 and 8
# tiles on a throwaway single-node cluster (tools/slurm/local_cluster.sh), as a Markdown table.
#
#   bash tools/slurm/bench_tiles.sh SCENE [-- LUMIS_RENDER_FLAG...]
#
# Default size 1920x1080; --width and --height after -- replace it.
# Environment: LUMIS (binary; default this checkout's target/release/lumis, refused when older
# than the sources, like the other benchmarks in tools/), TILE_COUNTS (default "1 2 4 8"),
# LUMIS_CPUS_PER_TASK (default: every CPU of the machine, so each tile has the whole node and
# the tiles run one after another: the table then shows the fixed cost of a tile, not a
# speed-up, which needs more nodes).
#
# Columns: wall = submit to the merge's end (merge.log); tile = the task's wall time inside
# its sbatch script (render_I.log), mean and max; load+build = lumis's own summary, mean per
# tile (the work every tile repeats); render, write = the sums over the tiles of lumis's render
# and write phases (a tile keeps its RGBA unexposed in 32-bit float, where the image defaults
# to half); merge = the merge job's wall time; Slurm between jobs = wall minus every job's own
# time (only when the jobs run one at a time, see above); same bytes = the merged EXR against
# a render without tiles.
# Needs root (or an installed Slurm), like tools/test_slurm.sh. Progress goes to stderr.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
# shellcheck source=tools/slurm/local_cluster.sh
source "$here/local_cluster.sh"

if [ "$#" -lt 1 ]; then
    echo "usage: bench_tiles.sh SCENE [-- LUMIS_RENDER_FLAG...]" >&2
    exit 2
fi
scene=$(realpath -- "$1")
shift
if [ "$#" -gt 0 ]; then
    [ "$1" = "--" ] || { echo "bench_tiles.sh: flags go after --" >&2; exit 2; }
    shift
fi
# 1920x1080 unless the flags give a size (lumis refuses a flag given twice).
flags=("$@")
case " $* " in
    *" --width"* | *" --height"*) ;;
    *) flags=(--width 1920 --height 1080 "$@") ;;
esac
read -r -a counts <<< "${TILE_COUNTS:-1 2 4 8}"
cpus=${LUMIS_CPUS_PER_TASK:-$(nproc)}
# With a whole node per tile the jobs run one after another, and the wall time not spent in
# them is Slurm's: queueing, launching, and starting the merge once the array is done.
serial=0
[ "$cpus" -lt "$(nproc)" ] || serial=1

if [ -n "${LUMIS:-}" ]; then
    lumis=$(realpath -- "$(command -v -- "$LUMIS")")
else
    lumis=$repo/target/release/lumis
    # A benchmark reports on this checkout's code or not at all (tools/README.md).
    if [ ! -x "$lumis" ] || [ -n "$(cd "$repo" &&
        find src Cargo.toml Cargo.lock -newer "$lumis" -print -quit)" ]; then
        echo "bench_tiles.sh: $lumis is missing or older than the sources;" \
            "run cargo build --release" >&2
        exit 2
    fi
fi

work=
cleanup() {
    cluster_stop
    [ -z "$work" ] || rm -rf -- "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

cluster_install
work=$(mktemp -d "${TMPDIR:-/tmp}/lumis-bench-tiles.XXXXXX")
# munged wants the path to its socket searchable by all users.
chmod 755 "$work"
cluster_start "$work/cluster"

# The reference: the same render in one piece, outside Slurm, with the same threads.
echo "bench_tiles.sh: reference render ($cpus threads)" >&2
t0=$(date +%s.%N)
"$lumis" render "$scene" "${flags[@]}" --threads "$cpus" -o "$work/whole.exr" 2> "$work/whole.log"
t1=$(date +%s.%N)

# The summary's phase times of one log, "load build render write"; the last attempt wins.
phases() {
    local n='\([0-9.]*\)s'
    sed -n "s/^time: load $n, build $n, render $n, write $n\$/\\1 \\2 \\3 \\4/p" "$1" | tail -n 1
}
read -r ref_load ref_build ref_render ref_write _ <<< "$(phases "$work/whole.log") 0 0 0 0"
# The value of key $2 in the last lumis-slurm line of log $1.
field() {
    grep '^lumis-slurm: task=' "$1" | tail -n 1 | tr ' ' '\n' | sed -n "s/^$2=//p"
}

rows=()
for n in "${counts[@]}"; do
    echo "bench_tiles.sh: $n tiles" >&2
    out=$work/n$n/full.exr
    mkdir -p "$work/n$n"
    t_submit=$(date +%s.%N)
    ids=$(LUMIS=$lumis LUMIS_CPUS_PER_TASK=$cpus bash "$here/submit.sh" "$scene" "$n" "$out" \
        -- "${flags[@]}")
    merge_id=$(sed -n 's/^merge=//p' <<< "$ids")
    if ! cluster_wait_job "$merge_id" 7200; then
        tail -n 20 "${out%.exr}.tiles"/logs/*.log >&2
        echo "bench_tiles.sh: $n tiles: merge $CLUSTER_JOB_STATES" >&2
        exit 1
    fi
    logs=${out%.exr}.tiles/logs
    merge_end=$(field "$logs/merge.log" end)
    merge_s=$(field "$logs/merge.log" seconds)
    per_tile=()
    for ((i = 0; i < n; i++)); do
        per_tile+=("$(field "$logs/render_$i.log" seconds) $(phases "$logs/render_$i.log")")
    done
    same=no
    cmp -s "$out" "$work/whole.exr" && same=yes
    rows+=("$(printf '%s\n' "${per_tile[@]}" | awk -v n="$n" -v wall_s="$t_submit" \
        -v wall_e="$merge_end" -v merge="$merge_s" -v same="$same" -v serial="$serial" '
        { task += $1; if ($1 > max) max = $1; lb += $2 + $3; render += $4; write += $5 }
        END {
            wall = wall_e - wall_s
            gaps = serial ? sprintf("%.2f", wall - task - merge) : "-"
            printf "| %d | %.2f | %.2f / %.2f | %.3f | %.2f | %.2f | %.2f | %s | %s |\n",
                n, wall, task / n, max, lb / n, render, write, merge, gaps, same }')")
done

order="tiles run one after another"
[ "$serial" = 1 ] || order="up to $(($(nproc) / cpus)) tiles at a time"
echo "Scene \`$(basename "$scene")\`, ${flags[*]}, $(nproc) CPUs, $cpus per tile task" \
    "($order), $(hostname -s)."
echo
awk -v w="$t0" -v e="$t1" -v l="$ref_load" -v b="$ref_build" -v r="$ref_render" \
    -v x="$ref_write" 'BEGIN {
    printf "Without Slurm or tiles: %.2f s wall, load+build %.3f s, render %.2f s, write %.2f s.\n",
        e - w, l + b, r, x }'
echo
echo "| tiles | wall, submit to merged (s) | tile task mean / max (s)" \
    "| load+build per tile (s) | render, sum (s) | write, sum (s) | merge (s)" \
    "| Slurm between jobs (s) | same bytes |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|:---:|"
printf '%s\n' "${rows[@]}"
