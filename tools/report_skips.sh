#!/usr/bin/env bash
# After ctest (make test): how many tests were skipped and why, from ctest's full log of the run
# (Testing/Temporary/LastTest.log). GoogleTest prints "FILE:LINE: Skipped" and then the test's reason;
# gtest_discover_tests maps a skip to ctest's "Skipped", so a skipped test does not pass silently.
log=${1:-Testing/Temporary/LastTest.log}
[ -f "$log" ] || exit 0
skipped=$(grep -c ': Skipped$' "$log")
if [ "$skipped" -eq 0 ]; then echo "0 tests skipped"; exit 0; fi
echo "$skipped tests skipped; reasons (count, message):"
awk 'found { print "  " $0; found = 0 } /: Skipped$/ { found = 1 }' "$log" | sort | uniq -c
