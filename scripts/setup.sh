#!/usr/bin/env bash
# The README's first command: installs what is missing, builds ray, and renders the
# bundled showpiece scene to showpiece.png.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target ray
./build/ray scenes/showpiece.xml 800 600 -o showpiece.png --stats
echo "rendered $(pwd)/showpiece.png"
