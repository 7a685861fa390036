#!/usr/bin/env bash
# Runs the Python blocks of docs/embedding.md as written, with the cs123ray module just built, in a
# folder where their relative paths (scenes/...) lead to the repository's scenes.
# Usage: docs_examples.sh PYTHON MODULE_DIR SOURCE_DIR WORK_DIR   (MODULE_DIR holds cs123ray)
set -u
python=$1 source=$(cd "$3" && pwd) work=$4
PYTHONPATH=$(cd "$2" && pwd)  # absolute: the blocks run in another folder
export PYTHONPATH
if ! "$python" -c "import numpy" 2> /dev/null; then
    echo "SKIPPED: numpy is not installed for $python (apt-get install python3-numpy)"; exit 0
fi
rm -rf "$work" && mkdir -p "$work/run" && work=$(cd "$work" && pwd)
ln -s "$source/scenes" "$work/run/scenes"
blocks=$(bash "$source/tests/code_blocks.sh" python "$source/docs/embedding.md" "$work" py) || { echo "$blocks"; exit 1; }
failures=0
for block in $blocks; do
    if (cd "$work/run" && "$python" "$block") > "$block.out" 2>&1; then
        echo "$(basename "$block"): ran"; tail -3 "$block.out"
    else
        echo "FAIL: docs/embedding.md's $(basename "$block") failed:"; cat "$block.out"; failures=$((failures + 1))
    fi
done
exit $((failures > 0))
