#!/usr/bin/env bash
# A page that shows a file of the repository shows it whole and as it is: the fenced block after the line
# `<!-- file: PATH -->` in DOC must equal REPO/PATH line for line.
# usage: doc_shows_file.sh REPO DOC PATH
set -euo pipefail
repo=$1; doc=$2; path=$3
[ -f "$repo/$path" ] || { echo "FAIL: $path does not exist"; exit 1; }
grep -qxF "<!-- file: $path -->" "$doc" || { echo "FAIL: $doc has no '<!-- file: $path -->' block"; exit 1; }
shown=$(awk -v marker="<!-- file: $path -->" '
  $0 == marker { found = 1; next }
  found == 1 && /^```/ { found = 2; next }
  found == 2 && /^```/ { exit }
  found == 2 { print }' "$doc")
if [ "$shown" != "$(cat "$repo/$path")" ]; then
  echo "FAIL: $doc shows a different $path:"; diff <(echo "$shown") "$repo/$path" || true; exit 1
fi
echo "$doc shows $path as it is"
