#!/usr/bin/env bash
# A self-contained folder for the GPU check on a machine that has a GPU's driver and nothing
# else of ours (no build, no PoCL, no Debian libraries, perhaps no package registry):
#   scripts/gpu_bundle.sh DIR [--build-dir BUILD]
#   ... carry DIR to the GPU machine, then, from any folder:  DIR/gpu_check.sh
# DIR gets `ray`, `ray_tests` (the kernel-versus-host tests) and `ray_bench`, every library
# they load beyond glibc in DIR/lib (found through an $ORIGIN rpath), `gpu_check.sh`, the
# bundled scenes and test data, the course corpus (when ../shared is beside the checkout)
# and images of the bundled scenes that PoCL's CPU device rendered here, which the GPU's
# images are held to. At most 64 MiB. Needs a build with its tests, PoCL and patchelf
# (scripts/install-deps.sh). DIR is written beside itself and renamed into place whole; an
# existing DIR is replaced only if it is a bundle.
set -euo pipefail
checkout=$(cd "$(dirname "$0")/.." && pwd)
build=$checkout/build dir=""
while [ $# -gt 0 ]; do
    case $1 in
        --build-dir) build=$(cd "$2" && pwd); shift 2 ;;
        -*) sed -n '2,12p' "$0" >&2; exit 2 ;;
        *) [ -z "$dir" ] || { sed -n '2,12p' "$0" >&2; exit 2; }; dir=$1; shift ;;
    esac
done
[ -n "$dir" ] || { sed -n '2,12p' "$0" >&2; exit 2; }
fail() { echo "gpu_bundle: $*" >&2; exit 1; }
command -v patchelf >/dev/null || fail "patchelf is missing: bash scripts/install-deps.sh"
for program in ray tests/ray_tests bench/ray_bench; do
    [ -x "$build/$program" ] || fail "$build/$program not found: build first (bash scripts/test.sh)"
done
if [ -e "$dir" ] && [ -n "$(ls -A "$dir")" ] && [ ! -f "$dir/bundle.txt" ]; then
    fail "$dir exists and is not a bundle: name a new folder"
fi
readonly max_bytes=$((64 * 1024 * 1024))
mkdir -p "$(dirname "$dir")"
dir=$(cd "$(dirname "$dir")" && pwd)/$(basename "$dir")
stage=$(mktemp -d "$dir.partial.XXXXXX")
trap 'rm -rf "$stage"' EXIT

# The programs, and each library they load that is not glibc's, under its soname.
# glibc's own libraries are the target's: they must match its dynamic loader.
glibc='^(linux-vdso|linux-gate|ld-linux[^ ]*|libc|libm|libdl|libpthread|librt|libresolv|libutil|libmvec)\.so'
mkdir -p "$stage/lib"
cp "$build/ray" "$build/tests/ray_tests" "$build/bench/ray_bench" "$stage/"
for program in ray ray_tests ray_bench; do
    ldd "$stage/$program" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | while read -r soname path; do
        [[ $soname =~ $glibc ]] && continue
        [ -f "$stage/lib/$soname" ] || cp -L "$path" "$stage/lib/$soname"
    done
    ldd "$stage/$program" | grep -q "not found" && fail "$program: a library is not found: $(ldd "$stage/$program" | grep "not found")"
    patchelf --set-rpath '$ORIGIN/lib' "$stage/$program"
done
chmod u+w "$stage"/lib/*
for library in "$stage"/lib/*; do patchelf --set-rpath '$ORIGIN' "$library"; done

# What the checks read: the check itself, scenes, test data, the course corpus.
install -m 755 "$checkout/scripts/gpu_check.sh" "$stage/gpu_check.sh"
cp -r "$checkout/scenes" "$stage/scenes"
mkdir -p "$stage/tests" && cp -r "$checkout/tests/data" "$stage/tests/data"
shared=${RAY_SHARED_DIR:-$checkout/../shared}
if [ -d "$shared/cs123" ]; then
    mkdir -p "$stage/shared" && cp -r "$shared/cs123" "$stage/shared/cs123"
else
    echo "gpu_bundle: no course corpus at $shared/cs123: the bundle checks the bundled scenes only" >&2
fi

# The CPU images, rendered here by the bundled ray itself on PoCL's CPU device.
mkdir -p "$stage/cpu-images"
readonly width=96 height=72
echo -e "# scene\twidth\theight\toptions\timage: rendered by PoCL's CPU device when the bundle was made" \
    >"$stage/cpu-images/list.tsv"
for scene in "$stage"/scenes/*.xml; do
    name=$(basename "$scene" .xml)
    "$stage/ray" "$scene" $width $height --device cpu --quiet -o "$stage/cpu-images/$name.png" ||
        fail "$name: PoCL's CPU device could not render it (is pocl-opencl-icd installed?)"
    echo -e "scenes/$name.xml\t$width\t$height\t\tcpu-images/$name.png" >>"$stage/cpu-images/list.tsv"
done

{
    echo "ray GPU bundle"
    echo "commit: $(git -C "$checkout" rev-parse --short HEAD 2>/dev/null || echo unknown)"
    echo "made: $(date -u '+%Y-%m-%d %H:%M UTC') on $(. /etc/os-release && echo "$PRETTY_NAME"), $(getconf GNU_LIBC_VERSION)"
    echo "needs: x86-64 Linux with glibc >= $(getconf GNU_LIBC_VERSION | cut -d' ' -f2) and a GPU's OpenCL driver"
    echo "cpu images: $("$stage/ray" --list-devices 2>/dev/null | awk '/^[0-9]+: / {name = $0} /^ *CPU,/ {print name; exit}')"
} >"$stage/bundle.txt"
bytes=$(du -sb "$stage" | cut -f1)
[ "$bytes" -le $max_bytes ] || fail "the bundle would take $bytes bytes, over 64 MiB ($max_bytes)"
echo "size: $bytes bytes" >>"$stage/bundle.txt"
chmod 755 "$stage"

rm -rf "$dir"
mv "$stage" "$dir"
trap - EXIT
echo "gpu_bundle: $dir, $((bytes / 1024 / 1024)) MiB ($bytes bytes); on the GPU machine run $(basename "$dir")/gpu_check.sh"
