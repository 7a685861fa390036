#!/usr/bin/env bash
# The GPU bundle (scripts/gpu_bundle.sh) is what a bare GPU machine can run: at most 64 MiB;
# every ELF file in it loads, outside the bundle, only glibc's libraries; its ray renders
# from another folder in an empty environment, to the same bytes as the build's ray; and its
# gpu_check.sh, here without a GPU (PoCL standing in as the only vendor), reports the machine,
# says that no GPU was found, and checks the bundle's images on the CPU device instead.
#   tests/gpu_bundle.sh BUILD/ray CHECKOUT [OUTPUT_DIR]   (as tests/CMakeLists.txt ray_script_test runs it)
set -uo pipefail
build=$(cd "$(dirname "$1")" && pwd)
checkout=$(cd "$2" && pwd)
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
failures=0
check() {  # check "what" command...: runs the command, prints ok or FAIL
    local what=$1; shift
    if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}
if ! command -v patchelf >/dev/null; then
    echo "SKIPPED: patchelf is missing (bash scripts/install-deps.sh)"
    exit 0
fi
if ! "$build/ray" --list-devices 2>/dev/null | grep -q CPU; then
    echo "SKIPPED: no OpenCL CPU device to make the bundle's images (install pocl-opencl-icd)"
    exit 0
fi

bundle=$work/bundle
bash "$checkout/scripts/gpu_bundle.sh" "$bundle" --build-dir "$build" || { echo "FAIL: the bundle was not made"; exit 1; }
bytes=$(du -sb "$bundle" | cut -f1)
echo "bundle: $bytes bytes, $(find "$bundle" -type f | wc -l) files"
check "at most 64 MiB" [ "$bytes" -le $((64 * 1024 * 1024)) ]

# ldd resolves each ELF file's libraries; outside the bundle only glibc's may be loaded.
glibc='^(linux-vdso\.so|linux-gate\.so|/lib64/ld-linux|ld-linux|libc\.so|libm\.so|libdl\.so|libpthread\.so|librt\.so|libresolv\.so|libutil\.so|libmvec\.so)'
outside_glibc() {
    local file=$1 bad
    bad=$(ldd "$file" | awk -v dir="$bundle/" '
        $2 == "=>" && $3 == "not" {print $1 " not found"; next}
        $2 == "=>" && index($3, dir) == 1 {next}
        {print $1}' | grep -Ev "$glibc" | grep -v "statically linked")
    [ -z "$bad" ] || echo "  $file loads from outside the bundle: $bad"
    [ -z "$bad" ]
}
elves=0
while IFS= read -r file; do
    if [ "$(head -c 4 "$file" | od -An -c | tr -d ' ')" = "177ELF" ]; then
        elves=$((elves + 1))
        check "ldd $(basename "$file"): inside the bundle or glibc" outside_glibc "$file"
    fi
done < <(find "$bundle" -type f)
check "the bundle has its programs and libraries ($elves ELF files)" [ "$elves" -ge 8 ]

# Its ray, from another folder, with no environment at all.
mkdir "$work/elsewhere"
(cd "$work/elsewhere" && env -i "$bundle/ray" "$bundle/scenes/shadows.xml" 64 48 --device ref --quiet -o bundled.png)
"$build/ray" "$checkout/scenes/shadows.xml" 64 48 --device ref --quiet -o "$work/built.png"
check "the bundle's ray renders --device ref from another folder under env -i, as the build's ray does" \
    cmp -s "$work/elsewhere/bundled.png" "$work/built.png"

# gpu_check.sh from another folder; PoCL's .icd as the only vendor, nothing else set.
mkdir "$work/vendors"
cp /etc/OpenCL/vendors/pocl.icd "$work/vendors/" 2>/dev/null || echo "libpocl.so.2" >"$work/vendors/pocl.icd"
(cd "$work/elsewhere" && env -i OCL_ICD_VENDORS="$work/vendors" POCL_CACHE_DIR="$work/pocl-cache" \
    "$bundle/gpu_check.sh" --report report.md >check.out 2>&1)
code=$?
report=$work/elsewhere/report.md
sed 's/^/  | /' "$report"
check "gpu_check.sh without a GPU exits 1" [ $code -eq 1 ]
check "its report names the machine and the drivers" grep -q "^kernel: Linux" "$report"
check "its report says that no GPU was found" grep -q "No GPU device" "$report"
check "the bundle's images agree on the CPU device" grep -Eq "All tests passed|test cases? passed" "$report"
check "the report shows no FAILED check" bash -c "[ -s '$report' ] && ! grep -q FAILED '$report'"

echo "gpu_bundle: $failures failures"
[ $failures -eq 0 ]
