#!/usr/bin/env bash
# Renders every bundled scene into docs/ for the README's gallery.
set -euo pipefail
cd "$(dirname "$0")/.."
ray=${RAY:-build/ray}
mkdir -p docs
for scene in scenes/*.xml; do
    name=$(basename "$scene" .xml)
    size="400 300"
    [ "$name" = showpiece ] && size="800 600"
    "$ray" "$scene" $size --quiet -o "docs/$name.png"
    echo "docs/$name.png"
done
