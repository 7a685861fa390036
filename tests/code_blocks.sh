#!/usr/bin/env bash
# Writes each fenced code block of one language in a Markdown file to a file of its own,
# so that tests compile and run the docs' examples as the docs write them:
#   code_blocks.sh LANGUAGE FILE.md OUT_DIR EXTENSION   →   OUT_DIR/block1.EXTENSION, ...
# Prints the files written; none is an error (the docs lost their examples).
set -eu
language=$1 markdown=$2 out=$3 extension=$4
mkdir -p "$out"
rm -f "$out"/block*."$extension"
awk -v language="$language" -v out="$out" -v extension="$extension" '
    /^```/ && inside { inside = 0; close(file); next }
    $0 == "```" language { inside = 1; count++; file = out "/block" count "." extension; printf "" > file; next }
    inside { print > file }
' "$markdown"
written=$(ls "$out"/block*."$extension" 2>/dev/null || true)
[ -n "$written" ] || { echo "FAIL: no \`\`\`$language block in $markdown"; exit 1; }
echo "$written"
