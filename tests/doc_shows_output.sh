#!/usr/bin/env bash
# A page's generated part equals what its command prints now: the lines between `<!-- NAME begin...-->`
# and `<!-- NAME end -->` in DOC must equal COMMAND's output. With --update, writes the output there instead
# (tools/update_docs.sh).
# usage: doc_shows_output.sh [--update] DOC NAME -- COMMAND...
set -euo pipefail
update=0
if [ "$1" = --update ]; then update=1; shift; fi
doc=$1; name=$2; shift 3
grep -q "^<!-- $name begin" "$doc" || { echo "FAIL: $doc has no '<!-- $name begin' line"; exit 1; }
grep -qxF "<!-- $name end -->" "$doc" || { echo "FAIL: $doc has no '<!-- $name end -->' line"; exit 1; }
output=$("$@")
if [ $update = 1 ]; then
  tmp=$(mktemp "$doc.XXXXXX")
  awk -v name="$name" -v file=<(printf '%s\n' "$output") '
    index($0, "<!-- " name " begin") == 1 { print; while ((getline line < file) > 0) print line; skip = 1; next }
    $0 == "<!-- " name " end -->" { skip = 0 }
    !skip { print }' "$doc" > "$tmp"
  cat "$tmp" > "$doc" && rm "$tmp"  # keeps the page's permissions
  echo "updated $doc ($name)"
  exit 0
fi
shown=$(awk -v name="$name" '
  index($0, "<!-- " name " begin") == 1 { found = 1; next }
  $0 == "<!-- " name " end -->" { exit }
  found { print }' "$doc")
if [ "$shown" != "$output" ]; then
  echo "FAIL: $doc's $name part differs from the output of: $*"; diff <(echo "$shown") <(echo "$output") || true
  echo "(tools/update_docs.sh rewrites it)"; exit 1
fi
echo "$doc shows the output of $* as it is"
