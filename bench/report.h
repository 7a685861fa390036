// What the bench prints and writes: the table of runs, the sphere-scaling curve, and JSON.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "ray_runs.h"

namespace bench {

struct BenchResults {
    RenderSize size;
    bool quick = false;
    std::string rayBinary;
    std::string scenesDir;
    double referenceTimeoutSeconds = 0;
    uint64_t referenceMaxPrimitives = 0;
    uint64_t plainMaxPrimitives = 0;
    std::vector<BenchScene> scenes;    // the records below point into these two
    std::vector<BenchDevice> devices;  // OpenCL devices first, then the reference and the plain one
    std::vector<RunRecord> runs;
    double totalWallSeconds = 0;
};

void printRunTable(const BenchResults& results, std::ostream& out);
void printSphereScaling(const BenchResults& results, std::ostream& out);
void writeResultsJson(const BenchResults& results, const std::filesystem::path& file);

}  // namespace bench
