# What `cmake --install` adds beyond the library (cmake/shared_library.cmake), and the Debian
# package made from it all: `cpack -G DEB` in the build folder writes ray_<version>_<arch>.deb,
# whose files are the install's under /usr:
#   bin/ray, lib/<arch>/libray*.so* (the library and ray's modules), include/ray/, the CMake
#   and pkg-config files, lib/python3/dist-packages/cs123ray*.so and cs123ray.pyi (Debian's
#   python3; python/CMakeLists.txt), share/man/man1/ray.1.gz, and the completions in
#   share/bash-completion/completions/ray and share/zsh/vendor-completions/_ray.
# Its dependencies are Debian's package names: the shared libraries' from dpkg-shlibdeps
# (CPACK_DEBIAN_PACKAGE_SHLIBDEPS), and what no ELF file names: an OpenCL driver (PoCL, the CPU
# one every machine can run), the Python the module is built for and NumPy.
install(FILES ${RAY_MANUAL_PAGE_GZ} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES ${RAY_BASH_COMPLETION} DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions)
install(FILES ${RAY_ZSH_COMPLETION} DESTINATION ${CMAKE_INSTALL_DATADIR}/zsh/vendor-completions)

set(CPACK_PACKAGE_NAME ray)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "ray tracer for CS123 scenefiles (OpenCL), with a live viewer and Python module")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
    "ray renders CS123 scenefiles (XML) with one OpenCL kernel, on PoCL's CPU backend or any GPU,\n"
    "checked against a double-precision host renderer. It holds the ray command (ray view, a\n"
    "modeler in the browser, and ray explain, the tree of rays of a pixel), the C++ library with\n"
    "its headers, CMake and pkg-config files, and the Python module cs123ray for Debian's python3.")
set(CPACK_PACKAGE_CONTACT "ray's maintainers <ray@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # ray_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "pocl-opencl-icd | opencl-icd")
if(RAY_PYTHON_DEBIAN_DEPENDS)
  string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS ", ${RAY_PYTHON_DEBIAN_DEPENDS}")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "bash-completion, man-db")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "zsh, jupyter-notebook, chromium")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION TRUE)
include(CPack)
