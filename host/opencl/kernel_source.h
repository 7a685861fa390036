// The OpenCL kernel's source files, embedded at build time (cmake/embed_kernel.cmake).
#pragma once

#include <string>
#include <vector>

namespace ray {

struct KernelSourceFile {
    const char* name;
    const char* text;
};

// In the order they are compiled: the shared layout header first, then cl/*.cl.
const std::vector<KernelSourceFile>& kernelSourceFiles();

// The files joined into one program source, each preceded by a #line directive so that
// build errors name the original file.
std::string kernelProgramSource();

}  // namespace ray
