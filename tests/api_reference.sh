#!/usr/bin/env bash
# The C++ API reference: Doxygen (docs/Doxyfile) over include/ray/ must build without a
# single warning (an undocumented public name, a malformed comment) and produce the pages
# of the API's main classes.
# Usage: api_reference.sh SOURCE_DIR OUTPUT_DIR
# Without doxygen it skips, saying so, except in CI (the CI environment variable set, as
# .ci/run does), where scripts/install-deps.sh installs it and its absence is a failure.
set -u
source=$(cd "$1" && pwd) out=$2

if ! command -v doxygen > /dev/null; then
    if [ -n "${CI:-}" ]; then
        echo "FAIL: doxygen is not installed, and CI must build the API reference (scripts/install-deps.sh installs it)"
        exit 1
    fi
    echo "SKIPPED: doxygen is not installed (apt-get install doxygen; scripts/install-deps.sh does)"
    exit 0
fi

rm -rf "$out" && mkdir -p "$out" && out=$(cd "$out" && pwd)
# docs/Doxyfile as it is, writing into the build folder; its INPUT is relative to the checkout.
cat > "$out/Doxyfile" << END
@INCLUDE = $source/docs/Doxyfile
OUTPUT_DIRECTORY = $out
WARN_LOGFILE = $out/warnings.log
END
(cd "$source" && doxygen "$out/Doxyfile") > "$out/doxygen.log" 2>&1
status=$?
if [ -s "$out/warnings.log" ]; then
    echo "FAIL: doxygen warns about the public headers ($(wc -l < "$out/warnings.log") lines):"
    sed "s#$source/##" "$out/warnings.log"
    exit 1
fi
if [ $status -ne 0 ]; then
    echo "FAIL: doxygen exited with status $status:"; cat "$out/doxygen.log"; exit 1
fi
for page in index.html namespaceray_1_1api.html classray_1_1api_1_1Renderer.html classray_1_1api_1_1Scene.html \
            structray_1_1api_1_1Settings.html classray_1_1api_1_1InputError.html; do
    [ -s "$out/html/$page" ] || { echo "FAIL: doxygen wrote no $page"; exit 1; }
done
echo "api_reference: $(ls "$out/html"/*.html | wc -l) pages, no warnings: $out/html/index.html"
