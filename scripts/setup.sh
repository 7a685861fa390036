#!/usr/bin/env bash
# The README's first command: installs what is missing, builds ray and its Python module
# cs123ray (installed into the user's site-packages of /usr/bin/python3, the Python
# Debian's pybind11 and NumPy are built for), and renders the bundled showpiece scene to
# showpiece.png.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
python=/usr/bin/python3
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE="$python"
cmake --build build -j"$(nproc)" --target ray cs123ray
site="$("$python" -c 'import site; print(site.getusersitepackages())')"
mkdir -p "$site"
cp build/python/cs123ray*.so "$site"/
"$python" -c 'import cs123ray; print("installed", cs123ray.__file__)'
./build/ray scenes/showpiece.xml 800 600 -o showpiece.png --stats
echo "rendered $(pwd)/showpiece.png"
