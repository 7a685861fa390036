#!/usr/bin/env bash
# The installed library as a user meets it (docs/embedding.md, "Embedding ray: the C++ API"):
#   - cmake --install into a fresh prefix;
#   - libray.so's dynamic symbols are ray::api's only (nm -D --defined-only);
#   - the manual page, the completions and the Python module with its stubs are installed
#     beside it (cmake/Packaging.cmake, python/CMakeLists.txt), the module importable there;
#   - the C++ examples of docs/embedding.md, taken from it, build with
#     `pkg-config --cflags --libs ray` and run with no LD_LIBRARY_PATH, in a folder where
#     the examples' relative paths (scenes/...) lead to the repository's scenes.
# Usage: installed_library.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -u
build=$(cd "$1" && pwd) source=$(cd "$2" && pwd) work=$3
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

rm -rf "$work" && mkdir -p "$work"
work=$(cd "$work" && pwd)  # absolute: pkg-config's ${pcfiledir}, and so the rpath, follow it
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; exit 1; }
library=$(ls "$prefix"/lib*/libray.so 2>/dev/null | head -1)
[ -n "$library" ] || { echo "FAIL: cmake --install installed no libray.so"; exit 1; }

# What the Debian package holds beside the library, under the prefix as under /usr.
for file in share/man/man1/ray.1.gz share/bash-completion/completions/ray share/zsh/vendor-completions/_ray; do
    [ -f "$prefix/$file" ] || fail "cmake --install put no $file in the prefix"
done
if ls "$build"/python/cs123ray*.so > /dev/null 2>&1; then  # built with pybind11
    site=$prefix/lib/python3/dist-packages
    [ -f "$site/cs123ray.pyi" ] || fail "cmake --install put no cs123ray.pyi beside the module"
    where=$(cd "$work" && PYTHONPATH=$site PYTHONNOUSERSITE=1 /usr/bin/python3 -c 'import cs123ray; print(cs123ray.__file__)') &&
        [ "${where#"$site"/}" != "$where" ] || fail "cs123ray does not import from $site: $where"
fi

# Every defined dynamic symbol is ray::api's (its functions, its classes' typeinfo and
# vtables), none of ray::api::detail's; and the API is there.
nm -D --defined-only --demangle "$library" | cut -d' ' -f3- > "$work/exports.txt"
outside=$(grep -vE '^((typeinfo|typeinfo name|vtable) for )?ray::api::' "$work/exports.txt" | grep -v '^$')
[ -z "$outside" ] || fail "libray.so exports more than ray::api ($(echo "$outside" | wc -l) symbols), e.g.:
$(echo "$outside" | head -5)"
grep -q 'ray::api::detail' "$work/exports.txt" && fail "libray.so exports ray::api::detail"
for needed in 'ray::api::Scene::load(' 'ray::api::Renderer::render(' 'typeinfo for ray::api::InputError'; do
    grep -qF "$needed" "$work/exports.txt" || fail "libray.so does not export $needed"
done
echo "libray.so exports $(wc -l < "$work/exports.txt") symbols, all ray::api"

# The C++ blocks of docs/embedding.md, built as a user would, run without LD_LIBRARY_PATH.
export PKG_CONFIG_PATH=$(dirname "$library")/pkgconfig
flags=$(pkg-config --cflags --libs ray) || { fail "pkg-config --cflags --libs ray"; flags=""; }
run=$work/run
mkdir -p "$run" && ln -s "$source/scenes" "$run/scenes"
blocks=$(bash "$source/tests/code_blocks.sh" cpp "$source/docs/embedding.md" "$work/examples" cpp) || { echo "$blocks"; exit 1; }
for block in $blocks; do
    program=${block%.cpp}
    # shellcheck disable=SC2086  # pkg-config's flags are words
    if ! c++ -Wall -Werror "$block" -o "$program" $flags 2> "$program.build.log"; then
        fail "docs/embedding.md's $(basename "$block") does not build with pkg-config:"; cat "$program.build.log"; continue
    fi
    if ! (cd "$run" && env -u LD_LIBRARY_PATH "$program") > "$program.out" 2> "$program.err"; then
        fail "docs/embedding.md's $(basename "$block") failed to run:"; cat "$program.err"
    else
        echo "$(basename "$block"): $(cat "$program.out")"
    fi
done

[ $failures -eq 0 ] && echo "installed_library: all passed"
exit $((failures > 0))
