#!/usr/bin/env bash
# The Debian package as README.md says to make it (cmake/Packaging.cmake): `cpack -G DEB` with
# the build folder's configuration writes ray_<version>_<arch>.deb, which holds the ray
# command and its modules, the library with its headers and CMake and pkg-config files, the
# Python module with its stubs for Debian's python3, ray(1) and the completions, and declares
# its dependencies by Debian's package names (an OpenCL driver, NumPy, and the libraries'
# packages dpkg-shlibdeps finds: OpenCL's loader, OpenImageIO for the module that uses it).
# Installing it is done by hand (README.md): a test does not change the machine's packages.
# Usage: debian_package.sh BUILD_DIR WORK_DIR. Prints SKIPPED without dpkg-deb and dpkg-shlibdeps.
set -u
build=$(cd "$1" && pwd) work=$2
for tool in dpkg-deb dpkg-shlibdeps cpack; do
    command -v "$tool" > /dev/null || { echo "SKIPPED: $tool is missing (apt-get install dpkg-dev)"; exit 0; }
done
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

rm -rf "$work" && mkdir -p "$work" && work=$(cd "$work" && pwd)
(cd "$build" && cpack -G DEB -B "$work") > "$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; echo "FAIL: cpack -G DEB"; exit 1; }
version=$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
package="$work/ray_${version}_$(dpkg --print-architecture).deb"
[ -f "$package" ] || { ls "$work"; echo "FAIL: cpack wrote no $(basename "$package")"; exit 1; }
echo "$(basename "$package"): $(du -k "$package" | cut -f1) KiB"

dpkg-deb -c "$package" | awk '{print $6}' | sed 's|^\./|/|' > "$work/files.txt"
for pattern in '^/usr/bin/ray$' '^/usr/lib/(.*/)?libray\.so' '^/usr/lib/(.*/)?libray_viewer\.so$' \
               '^/usr/lib/(.*/)?libray_oiio\.so$' '^/usr/include/ray/ray\.h$' '^/usr/lib/(.*/)?pkgconfig/ray\.pc$' \
               '^/usr/lib/(.*/)?cmake/ray/rayConfig\.cmake$' '^/usr/lib/python3/dist-packages/cs123ray\.cpython-.*\.so$' \
               '^/usr/lib/python3/dist-packages/cs123ray\.pyi$' '^/usr/share/man/man1/ray\.1\.gz$' \
               '^/usr/share/bash-completion/completions/ray$' '^/usr/share/zsh/vendor-completions/_ray$'; do
    grep -qE "$pattern" "$work/files.txt" || fail "the package holds nothing matching $pattern"
done
outside=$(grep -vE '^/usr(/|$)' "$work/files.txt")
[ -z "$outside" ] || fail "the package has files outside /usr: $outside"

depends=$(dpkg-deb -f "$package" Depends)
echo "Depends: $depends"
for needed in 'pocl-opencl-icd' 'python3-numpy' 'python3 \(>= 3\.' 'ocl-icd-libopencl1|libopencl1' 'libopenimageio' \
              'libpng16' 'libexpat1'; do
    echo "$depends" | grep -qE "$needed" || fail "the package does not depend on $needed"
done
# The manual page in the package is the build's (reference_pages checks that one against --help).
dpkg-deb --fsys-tarfile "$package" | tar -xO ./usr/share/man/man1/ray.1.gz | gzip -dc | cmp -s - "$build/ray.1" ||
    fail "the package's ray.1.gz is not build/ray.1"

[ $failures -eq 0 ] && echo "debian_package: all passed"
exit $((failures > 0))
