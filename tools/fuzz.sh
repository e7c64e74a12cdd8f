#!/usr/bin/env bash
# Runs both libFuzzer targets at once (one per core) for SECONDS each: tools/fuzz.sh BUILD_DIR SECONDS.
# The corpora grow in BUILD_DIR/corpus/TARGET (seeded from tests/data and the small shared .gltf scenes);
# crashes, hangs and leaks land in BUILD_DIR/findings/; logs in BUILD_DIR/fuzz_TARGET.log. Exits 1 if
# anything was found.
# Needs the targets built: `make fuzz` does both.
# Fork mode with -ignore_crashes: a finding is saved and the run goes on for the whole time.
set -euo pipefail
build=$1 seconds=$2
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$build/corpus/gltf" "$build/corpus/shot_script" "$build/findings"
cp "$src"/tests/data/{broken,materials,animated}/*.{gltf,glb} "$build/corpus/gltf/" 2>/dev/null || true
find "$src/../shared/scenes" -name '*.gltf' -size -256k -exec cp {} "$build/corpus/gltf/" \; 2>/dev/null || true
cp "$src"/tests/data/scripts/*.json "$build/corpus/shot_script/"

run() {  # target: gltf or shot_script
  "$build/candela_fuzz_$1" "$build/corpus/$1" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -print_funcs=0 -artifact_prefix="$build/findings/$1-" > "$build/fuzz_$1.log" 2>&1 || true
}
run gltf &
run shot_script &
wait

found=0
for t in gltf shot_script; do
  echo "$t: $(grep -E '^#[0-9]+' "$build/fuzz_$t.log" | tail -1)"
  grep -E '^stat::number_of_executed_units' "$build/fuzz_$t.log" || true
done
for f in "$build"/findings/*; do
  [ -e "$f" ] || continue
  echo "finding: $f"
  found=1
done
exit $found
