#!/usr/bin/env bash
# ThreadSanitizer check (`make test-tsan`): a few small frames of every method with each denoiser, on the
# animated city (moving instances, a refitted light tree) with 2 worker threads. tools/tsan_frames.sh CANDELA
# Any data race report fails the run (exit status 66).
set -euo pipefail
candela=$1
src=$(cd "$(dirname "$0")/.." && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1 suppressions=$src/tests/tsan.supp"
for method in pt direct restir-di restir; do
  for denoise in none bilateral svgf; do
    echo "tsan: $method, denoise $denoise"
    "$candela" render builtin:city --method "$method" --denoise "$denoise" --threads 2 --width 48 --height 32 \
      --frames 3 --no-accumulate --out "$out/frame.png" -q
  done
done
echo "tsan: 12 runs clean"
