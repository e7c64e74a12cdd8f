#!/usr/bin/env bash
# The job array's script run by hand, as a Slurm task would run it (for machines without Slurm; the real
# submission is farm_test.sh): with SLURM_ARRAY_TASK_ID=1 and FRAMES_PER_TASK=4, task 1 writes frames 4..7
# of tests/data/scripts/farm_twelve_frames.json and nothing else; without SHOT it fails and names SHOT.
# usage: sbatch_without_slurm.sh CANDELA WORKDIR
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
candela=$(realpath "$1"); work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"; cd "$work"
export SLURM_ARRAY_TASK_ID=1 SLURM_CPUS_PER_TASK=2 FRAMES_PER_TASK=4 CANDELA=$candela
if bash "$repo/docs/farm/render_shot.sbatch" 2> no_shot.txt; then fail "the script ran without SHOT"; fi
grep -q "SHOT" no_shot.txt || fail "without SHOT: $(cat no_shot.txt)"
SHOT=$repo/tests/data/scripts/farm_twelve_frames.json bash "$repo/docs/farm/render_shot.sbatch" 2> log.txt ||
  fail "task 1 failed: $(cat log.txt)"
grep -q "frames 4:7, 0 already written, 4 to render (+0 warm-up)" log.txt || fail "task 1's plan: $(cat log.txt)"
[ "$(cd out && ls frame_*.png | tr '\n' ' ')" = "frame_0004.png frame_0005.png frame_0006.png frame_0007.png " ] ||
  fail "task 1 wrote: $(ls out)"
echo "task 1 rendered frames 4..7"
