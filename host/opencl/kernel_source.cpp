#include "opencl/kernel_source.h"

namespace ray {

std::string kernelProgramSource() {
    std::string source;
    for (const KernelSourceFile& file : kernelSourceFiles()) {
        source += "#line 1 \"";
        source += file.name;
        source += "\"\n";
        source += file.text;
        source += "\n";
    }
    return source;
}

}  // namespace ray
