// The OpenCL kernel's source files, embedded at build time (cmake/embed_kernel.cmake).
#pragma once

#include <string>
#include <vector>

namespace ray {

struct KernelSourceFile {
    const char* name;
    const char* text;
};

// In the order they are compiled (CMakeLists.txt RAY_CL_SOURCES), each named by its path
// under cl/; a lane template appears once for each of its instances.
const std::vector<KernelSourceFile>& kernelSourceFiles();

// The files joined into one program source, each preceded by a #line directive so that
// build errors name the original file.
std::string kernelProgramSource();

}  // namespace ray
