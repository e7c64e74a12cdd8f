#!/usr/bin/env bash
# Frame sequences from a shot script (tests/data/scripts/ten_frames.json: ReSTIR DI with temporal reuse,
# history reset every 5 frames, a moving camera, a moving instance and a light power step):
#  1. interrupted after 4 frames (--stop-after) and resumed: the resumed run reports 4 finished frames,
#     leaves their files untouched (same mtimes) and writes the other 6;
#  2. two shard processes (--frames 0:6 and 7:9, run at the same time; the second warms up on 5 and 6)
#     and the resumed run equal a single run: PNGs byte for byte, EXRs pixel for pixel (check_outputs' `same`,
#     all in one process; EXR headers carry a capture date, so their bytes differ), and the shard's stats CSV
#     has its columns, a total row per frame and no dropped non-finite value.
# usage: sequence_test.sh CANDELA CHECK_OUTPUTS SCRIPT WORKDIR
set -euo pipefail
candela=$1; check_outputs=$2; script=$3; work=$4
rm -rf "$work"; mkdir -p "$work"/single "$work"/resume "$work"/shards
fail() { echo "FAIL: $*"; exit 1; }

cd "$work/resume"
"$candela" render --script "$script" --stop-after 4 -q
[ "$(ls out/frame_*.png | wc -l)" = 4 ] || fail "--stop-after 4 wrote $(ls out/frame_*.png | wc -l) frames"
stat -c '%n %.9Y' out/*_000[0-3].* > before.txt
"$candela" render --script "$script" 2> log.txt
grep -q "4 already written, 6 to render" log.txt || fail "resume did not skip the 4 finished frames: $(cat log.txt)"
stat -c '%n %.9Y' out/*_000[0-3].* > after.txt
cmp -s before.txt after.txt || fail "finished frames were rewritten: $(diff before.txt after.txt)"
[ "$(ls out/frame_*.png | wc -l)" = 10 ] || fail "resumed run did not finish the sequence"

cd "$work/single"
"$candela" render --script "$script" -q
cd "$work/shards"
"$candela" render --script "$script" --frames 0:6 -q & first=$!
"$candela" render --script "$script" --frames 7:9 -q
wait $first
[ -s out/stats_0-6.csv ] && [ -s out/stats_7-9.json ] || fail "shard stats missing"
# The stats CSV: its header, one row per stage and frame plus "total", and no non-finite value dropped.
[ "$(head -1 out/stats_0-6.csv)" = "frame,written,time_s,spp,stage,ms,rays,non_finite" ] || fail "stats CSV header: $(head -1 out/stats_0-6.csv)"
[ "$(grep -c ',total,' out/stats_0-6.csv)" = 7 ] || fail "stats CSV has $(grep -c ',total,' out/stats_0-6.csv) total rows for 7 frames"
awk -F, 'NR > 1 && $8 != 0 { bad = 1 } END { exit bad }' out/stats_0-6.csv || fail "stats CSV reports non-finite values"

# Every frame's PNG byte for byte, and its EXRs (image and motion) pixel for pixel in one check_outputs run.
same=()
for run in shards resume; do
  for f in 0 1 2 3 4 5 6 7 8 9; do
    n=$(printf %04d $f)
    cmp -s "$work/single/out/frame_$n.png" "$work/$run/out/frame_$n.png" || fail "$run frame $f PNG differs"
    for exr in frame motion; do same+=(same "$work/$run/out/${exr}_$n.exr" "$work/single/out/${exr}_$n.exr"); done
  done
done
"$check_outputs" "${same[@]}" || fail "EXRs differ from the single run's"
echo "resume and shards match the single run"
