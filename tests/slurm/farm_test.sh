#!/usr/bin/env bash
# The render farm for real (make test-farm): brings up a one-node Slurm cluster (local_cluster.sh), submits
# the documented job array (docs/farm/render_shot.sbatch) over tests/data/scripts/farm_twelve_frames.json
# (12 frames, 3 tasks x 4, history reset every 4, ReSTIR DI + SVGF at 320x180) and checks:
#  1. sbatch --wait exits 0 and the 12 PNGs equal a single local run byte for byte;
#  2. a task whose frames lie outside the shot fails, and sbatch --wait returns its exit status (2) with
#     candela's message in the task's log;
#  3. failure drill: the array again, task 1 cancelled (scancel JOB_1) once its first frame is written; the
#     re-submitted array renders only the missing frames (the tasks' logs and task 1's stats say so), leaves
#     the finished files untouched (same mtimes) and no temporary files, and all 12 PNGs equal the single run.
# Skips (exit 0, "SKIP:" and the reason) when not root, when Slurm is not installed or when the cluster
# cannot start; with CANDELA_FARM_STRICT=1 (set by .ci/run) each of these is a failure instead. The default
# WORKDIR (a new temporary directory) is removed after a pass.
# usage: farm_test.sh CANDELA [WORKDIR]   (make test-farm: WORKDIR build/farm)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
candela=$(realpath "$1")
own_work=0
[ -n "${2:-}" ] || own_work=1
work=${2:-$(mktemp -d /tmp/candela-farm.XXXXXX)}
sbatch_file=$repo/docs/farm/render_shot.sbatch
shot=$repo/tests/data/scripts/farm_twelve_frames.json
skip() {
  [ "${CANDELA_FARM_STRICT:-0}" = 1 ] && fail "cannot run (CANDELA_FARM_STRICT=1): $*"
  echo "SKIP: farm test: $*"; exit 0
}
fail() { echo "FAIL: farm test: $*"; [ -n "${CLUSTER_DIR:-}" ] && cluster_log_tail; exit 1; }

[ "$(id -u)" = 0 ] || skip "slurmd must run as root"
for c in munged slurmctld slurmd sbatch squeue scancel sinfo; do
  command -v $c > /dev/null || skip "$c is not installed (make test-farm installs slurmctld, slurmd, slurm-client, munge)"
done
rm -rf "$work"; mkdir -p "$work"/single "$work"/farm/log "$work"/exit/log "$work"/drill/log
source "$repo/tests/slurm/local_cluster.sh"
trap cluster_stop EXIT
# The cluster's own directory is short (a unix socket path holds at most 107 bytes) and goes with it.
if ! cluster_start "$(mktemp -d /tmp/candela-slurm.XXXXXX)"; then
  skip "the Slurm cluster did not start (logs above)"
fi
echo "Slurm cluster up: $(sinfo -h -N -o '%N %c CPUs %T')"

# submit DIR ARRAY [sbatch options]: the documented script from DIR, one CPU per task, logs in DIR/log.
submit() {
  local dir=$1 array=$2; shift 2
  (cd "$dir" && sbatch --array="$array" --cpus-per-task=1 --output=log/%a.out \
    --export=ALL,SHOT="$shot",FRAMES_PER_TASK=4,CANDELA="$candela" "$@" "$sbatch_file")
}
same_as_single() {
  local f n
  for f in $(seq 0 11); do
    n=$(printf %04d $f)
    cmp -s "$work/single/out/frame_$n.png" "$1/out/frame_$n.png" || fail "$1: frame $f differs from the single run"
  done
}

(cd "$work/single" && "$candela" render --script "$shot" -q)

# 1. The array as documented.
status=0; submit "$work/farm" 0-2 --wait > /dev/null || status=$?
[ $status = 0 ] || fail "sbatch --wait exited $status: $(cat "$work"/farm/log/*)"
same_as_single "$work/farm"
for t in 0 1 2; do
  grep -q "0 already written, 4 to render (+0 warm-up)" "$work/farm/log/$t.out" || fail "task $t log: $(cat "$work/farm/log/$t.out")"
done
echo "1. 3 tasks x 4 frames equal the single run"

# 2. A task outside the shot: its exit status reaches sbatch --wait.
status=0; submit "$work/exit" 3 --wait > /dev/null || status=$?
[ $status = 2 ] || fail "a task with frames 12:15 of a 12-frame shot: sbatch --wait exited $status, expected 2"
grep -q "frames 12:15: outside .*farm_twelve_frames.json's frames 0:11" "$work/exit/log/3.out" ||
  fail "task 3 log: $(cat "$work/exit/log/3.out")"
echo "2. a failing task's exit status (2) reaches sbatch --wait"

# 3. Failure drill: cancel task 1 after its first frame, then re-submit.
job=$(submit "$work/drill" 0-2 --parsable)
for i in $(seq 2400); do [ -e "$work/drill/out/frame_0004.png" ] && break; sleep 0.05; done
scancel "${job}_1"
for i in $(seq 240); do [ -z "$(squeue -h -j "$job")" ] && break; sleep 0.5; done
[ -z "$(squeue -h -j "$job")" ] || fail "the drill's array did not end in 120 s"
kept=$(ls "$work"/drill/out/frame_000[4-7].png 2> /dev/null | wc -l)
[ "$kept" -ge 1 ] && [ "$kept" -lt 4 ] || fail "task 1 wrote $kept of its 4 frames before scancel (expected 1 to 3)"
grep -q CANCELLED "$work/drill/log/1.out" || fail "task 1's log does not say it was cancelled: $(cat "$work/drill/log/1.out")"
stat -c '%n %.9Y' "$work"/drill/out/frame_*.png > "$work/drill/before.txt"
status=0; submit "$work/drill" 0-2 --wait > /dev/null || status=$?
[ $status = 0 ] || fail "re-submitted array: sbatch --wait exited $status: $(cat "$work"/drill/log/*)"
for t in 0 2; do
  grep -q "4 already written, 0 to render" "$work/drill/log/$t.out" || fail "re-run task $t log: $(cat "$work/drill/log/$t.out")"
done
grep -q "$kept already written, $((4 - kept)) to render (+$kept warm-up)" "$work/drill/log/1.out" ||
  fail "re-run task 1 ($kept frames kept) log: $(cat "$work/drill/log/1.out")"
written=$(awk -F, '$5 == "total" && $2 == 1 { printf "%s ", $1 }' "$work/drill/out/stats_4-7.csv")
[ "$written" = "$(seq -s ' ' $((4 + kept)) 7) " ] || fail "re-run task 1 wrote frames '$written' (kept $kept)"
stat -c '%n %.9Y' $(cut -d' ' -f1 "$work/drill/before.txt") | cmp -s - "$work/drill/before.txt" ||
  fail "finished frames were rewritten"
leftovers=$(ls -A "$work/drill/out" | grep -c '\.tmp\.' || true)
[ "$leftovers" = 0 ] || fail "temporary files left in out/: $(ls -A "$work/drill/out")"
same_as_single "$work/drill"
echo "3. drill: task 1 cancelled after $kept frames; the re-submitted array rendered only frames $written; all equal the single run"
echo "farm test passed"
[ $own_work = 1 ] && rm -rf "$work"
exit 0
