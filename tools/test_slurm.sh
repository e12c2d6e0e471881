#!/usr/bin/env bash
# End-to-end test of tools/slurm/ on a real single-node Slurm cluster started here.
#
#   bash tools/test_slurm.sh            (LUMIS=path overrides the binary)
#
# 1. installs slurm-wlm and munge with apt-get if missing (root; fails, never skips, without)
# 2. starts munged, slurmctld and slurmd in a temp dir (tools/slurm/local_cluster.sh)
# 3. renders a small scene as 4 tiles through tools/slurm/submit.sh, waits for the merge
# 4. checks the merged EXR is byte-identical to the same render without tiles
# 5. checks that `lumis merge` refuses a missing, a duplicated and a foreign tile, and that a
#    failing tile render cancels the merge job instead of leaving it pending
# The daemons it started are stopped by pid and the temp dir removed on every exit path, so a
# second run starts clean. The last line is PASS or FAIL.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=tools/slurm/local_cluster.sh
source "$repo/tools/slurm/local_cluster.sh"

work=
failure="exited early"
finish() {
    local status=$?
    cluster_stop
    [ -z "$work" ] || rm -rf -- "$work"
    if [ "$status" = 0 ]; then
        echo "test_slurm: PASS"
    else
        echo "test_slurm: FAIL: $failure"
    fi
    exit "$status"
}
trap finish EXIT
# A signal becomes an ordinary exit, so that the EXIT trap cleans up.
trap 'failure="interrupted"; exit 130' INT TERM

fail() {
    failure=$1
    exit 1
}

# Prints every log of a tiled render's directory (after a failure).
show_logs() {
    local f
    for f in "$1"/logs/*.log; do
        [ -f "$f" ] || continue
        echo "---- $f"
        tail -n 40 "$f"
    done
}

# Seconds since $1 (a date +%s.%N), to the millisecond.
since() {
    awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'
}

cluster_install || fail "slurm-wlm/munge are missing and could not be installed"

# The binary: $LUMIS as given, else this checkout's release build, rebuilt when missing or
# older than the sources (CI has built it already; then this costs nothing).
if [ -n "${LUMIS:-}" ]; then
    lumis=$(realpath -- "$(command -v -- "$LUMIS")")
else
    lumis=$repo/target/release/lumis
    if [ ! -x "$lumis" ] || [ -n "$(cd "$repo" &&
        find src Cargo.toml Cargo.lock -newer "$lumis" -print -quit)" ]; then
        echo "test_slurm: building $lumis"
        (cd "$repo" && cargo build --release --locked)
    fi
fi
# Read whole (not `| grep -q`, whose early exit can kill lumis with SIGPIPE under pipefail).
help=$("$lumis" render --help) || fail "$lumis render --help failed"
[[ "$help" == *--tile* ]] ||
    fail "$lumis has no 'render --tile' (needs the tiled render of issue 15)"
"$lumis" merge --help > /dev/null || fail "$lumis has no 'merge' (needs issue 15's lumis merge)"

# The paper's scene beside the checkout in CI (../shared), else the repo's own.
scene=$repo/../shared/paper-scenes/scenes/ballsOnAPlane.scn
[ -f "$scene" ] || scene=$repo/scenes/default.toml
# submit.sh hands the tiles the scene's real path, and the header records the path as given
# (lumis/replay): the reference render names it the same way.
scene=$(realpath -- "$scene")
flags=(--width 160 --height 96)
tiles=4

work=$(mktemp -d "${TMPDIR:-/tmp}/lumis-test-slurm.XXXXXX")
# munged wants the path to its socket searchable by all users.
chmod 755 "$work"
t0=$(date +%s.%N)
cluster_start "$work/cluster" 2>&1 || fail "the local cluster did not start"
echo "test_slurm: cluster up in $(since "$t0") s"

# The tiled render through the real scripts, as a user would run it.
mkdir -p "$work/out"
t0=$(date +%s.%N)
ids=$(LUMIS=$lumis bash "$repo/tools/slurm/submit.sh" "$scene" "$tiles" "$work/out/full.exr" \
    -- "${flags[@]}") || fail "submit.sh failed"
array_id=$(sed -n 's/^array=//p' <<< "$ids")
merge_id=$(sed -n 's/^merge=//p' <<< "$ids")
if [ -z "$array_id" ] || [ -z "$merge_id" ]; then
    fail "submit.sh printed no job ids: $ids"
fi
echo "test_slurm: submitted $tiles tiles of $(realpath -- "$scene"):" \
    "array=$array_id merge=$merge_id"
tile_dir=$work/out/full.tiles
if ! cluster_wait_job "$merge_id" 300; then
    show_logs "$tile_dir"
    fail "merge job $merge_id: $CLUSTER_JOB_STATES"
fi
cluster_wait_job "$array_id" 10 || fail "tile array $array_id: $CLUSTER_JOB_STATES"
echo "test_slurm: $tiles tiles rendered and merged through Slurm in $(since "$t0") s"
grep -h '^lumis-slurm: task=' "$tile_dir"/logs/*.log

# The same render in one piece must give the same bytes.
t0=$(date +%s.%N)
"$lumis" render "$scene" "${flags[@]}" --quiet -o "$work/whole.exr" ||
    fail "the reference render failed"
echo "test_slurm: reference render (no tiles) in $(since "$t0") s"
cmp "$work/out/full.exr" "$work/whole.exr" ||
    fail "the merged EXR differs from the render without tiles"
echo "test_slurm: merged EXR byte-identical to the render without tiles" \
    "($(stat -c %s "$work/whole.exr") bytes)"

# lumis merge must refuse incomplete or mixed sets: each must exit non-zero and write nothing.
t=$tile_dir
refuses() {
    local what=$1 out="$work/refused.exr"
    shift
    if "$lumis" merge "$@" -o "$out" 2> "$work/refused.err"; then
        fail "lumis merge accepted $what"
    fi
    [ ! -e "$out" ] || fail "lumis merge refused $what but wrote $out"
    echo "test_slurm: lumis merge refuses $what: $(head -n 1 "$work/refused.err")"
}
"$lumis" render "$scene" "${flags[@]}" --tile "2/$tiles" --seed 1 --quiet \
    -o "$work/foreign_tile_2.exr" || fail "rendering a tile with another seed failed"
refuses "a set without tile 2" "$t/tile_0.exr" "$t/tile_1.exr" "$t/tile_3.exr"
refuses "a duplicated tile" "$t/tile_0.exr" "$t/tile_1.exr" "$t/tile_1.exr" "$t/tile_3.exr"
refuses "a tile of another seed" "$t/tile_0.exr" "$t/tile_1.exr" "$work/foreign_tile_2.exr" \
    "$t/tile_3.exr"
rm "$t/tile_2.exr"
refuses "a deleted tile file" "$t/tile_0.exr" "$t/tile_1.exr" "$t/tile_2.exr" "$t/tile_3.exr"

# A tile that fails (here: a flag lumis rejects) must fail the array and cancel the merge, not
# leave it pending on a dependency that can never be met.
ids=$(LUMIS=$lumis bash "$repo/tools/slurm/submit.sh" "$scene" 2 "$work/out/bad.exr" \
    -- --no-such-flag) || fail "submit.sh failed"
array_id=$(sed -n 's/^array=//p' <<< "$ids")
merge_id=$(sed -n 's/^merge=//p' <<< "$ids")
if cluster_wait_job "$merge_id" 120; then
    fail "the merge of a failed tile array ran"
fi
case $CLUSTER_JOB_STATES in
    CANCELLED) ;;
    *) fail "the merge of a failed tile array ended $CLUSTER_JOB_STATES, not CANCELLED" ;;
esac
cluster_wait_job "$array_id" 30 && fail "a tile array with a bad flag completed"
[ ! -e "$work/out/bad.exr" ] || fail "a failed tiled render wrote its output"
ls "$work/out/bad.tiles"/tile_*.exr > /dev/null 2>&1 && fail "a failed tile left a tile file"
echo "test_slurm: a failing tile render fails the array ($CLUSTER_JOB_STATES) and cancels the merge"
