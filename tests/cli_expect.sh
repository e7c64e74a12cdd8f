#!/usr/bin/env bash
# Runs a candela command line and checks how it ends.
#   cli_expect.sh fail STATUS REGEX OUTPUT -- CMD...   must exit with STATUS (2: bad input), print an
#                                               `error:` line matching REGEX on stderr, and leave no OUTPUT file
#                                               behind, nor a temporary file named after it
#   cli_expect.sh ok FILE... -- CMD... [--then CHECK...]
#                                               must exit 0 and write every FILE (removed first); then
#                                               CHECK (tests/check_outputs.cpp: the files' content) must exit 0
set -u
mode=$1; shift
args=()
while [ "$1" != "--" ]; do args+=("$1"); shift; done
shift
cmd=()
while [ $# -gt 0 ] && [ "$1" != "--then" ]; do cmd+=("$1"); shift; done
[ $# -gt 0 ] && shift
check=("$@")
set -- "${cmd[@]}"
if [ "$mode" = fail ]; then
  status=${args[0]}; regex=${args[1]}; output=${args[2]}
  rm -f "$output"
  err=$("$@" 2>&1 >/dev/null); rc=$?
  [ $rc -eq "$status" ] || { echo "expected exit $status, got $rc: $err"; exit 1; }
  echo "$err" | grep -Eq -- "^error: .*$regex" || { echo "stderr has no 'error: ...$regex' line: $err"; exit 1; }
  [ ! -e "$output" ] || { echo "$output was written"; exit 1; }
  # This test's temporary files only (the writers name them ".<stem>...tmp..."; a test's files are named after it):
  # the tests run in parallel in one directory, where another test's file may be half-written at this moment.
  stem=$(basename "${output%.*}")
  ls "$(dirname "$output")/.$stem"*.tmp* >/dev/null 2>&1 && { echo "temporary file left behind"; exit 1; }
  exit 0
fi
for f in "${args[@]}"; do rm -f "$f"; done
"$@" || { echo "command failed with $?"; exit 1; }
for f in "${args[@]}"; do [ -s "$f" ] || { echo "$f missing"; exit 1; }; done
[ ${#check[@]} -eq 0 ] || "${check[@]}" || { echo "content check failed: ${check[*]}"; exit 1; }
exit 0
