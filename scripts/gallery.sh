#!/usr/bin/env bash
# Renders every bundled scene into docs/ for the gallery, docs/gallery.md.
set -euo pipefail
cd "$(dirname "$0")/.."
ray=${RAY:-build/ray}
mkdir -p docs
for scene in scenes/*.xml; do
    name=$(basename "$scene" .xml)
    [ "$name" = texture_filtering ] && continue  # rendered once per filter, below
    size="400 300"
    [ "$name" = showpiece ] && size="800 600"
    # Per-scene options: a motion's sweep needs many stochastic samples to look smooth
    # (the default course mode takes 4 to 64 samples, each at its own shutter time).
    options=""
    [ "$name" = motion_blur ] && options="--aa stratified --samples 64"
    "$ray" "$scene" $size $options --quiet -o "docs/$name.png"
    echo "docs/$name.png"
done
# The texture filters side by side on the receding checkerboard.
for filter in nearest bilinear trilinear; do
    "$ray" scenes/texture_filtering.xml 400 300 --texture-filter $filter --quiet -o "docs/texture_filter_$filter.png"
    echo "docs/texture_filter_$filter.png"
done
# Antialiasing modes side by side on the edges and penumbras of the shadows scene.
for mode in "off" "course" "stratified --samples 16" "adaptive --samples 16"; do
    name=$(echo "$mode" | cut -d' ' -f1)
    "$ray" scenes/shadows.xml 400 300 --aa $mode --quiet -o "docs/aa_$name.png"
    echo "docs/aa_$name.png"
done
