#include "ray_runs.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "child_process.h"

namespace bench {

namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& file) {
    std::ifstream in(file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}


std::string fileStem(const BenchScene& scene, const BenchDevice& device, Phase phase) {
    return scene.name + "." + device.label + "." + phaseName(phase);
}

std::vector<std::string> rayArguments(const RayInvocation& invocation, const BenchScene& scene,
                                      const BenchDevice& device, const fs::path& statsFile) {
    const RenderSize& size = invocation.size;
    std::vector<std::string> args = {invocation.rayBinary.string(), scene.file.string(), std::to_string(size.width),
                                     std::to_string(size.height), std::to_string(size.depth)};
    if (scene.rayOptions.empty()) args.insert(args.end(), {"--aa", "off"});
    else args.insert(args.end(), scene.rayOptions.begin(), scene.rayOptions.end());
    args.insert(args.end(), {"--device", device.argument, "--quiet", "--stats-json", statsFile.string(), "-o",
                             (invocation.workDir / "image.png").string()});
    args.insert(args.end(), device.extraArguments.begin(), device.extraArguments.end());
    return args;
}

// ray reads RAY_CACHE_DIR; the OpenCL drivers keep caches of their own (PoCL's, NVIDIA's),
// which would make a "cold" build warm, so they are pointed into the same fresh folder.
std::vector<std::pair<std::string, std::string>> cacheEnvironment(const fs::path& cacheDir) {
    if (cacheDir.empty()) return {};
    return {{"RAY_CACHE_DIR", (cacheDir / "ray").string()},
            {"POCL_CACHE_DIR", (cacheDir / "pocl").string()},
            {"CUDA_CACHE_PATH", (cacheDir / "cuda").string()}};
}

}  // namespace

const char* phaseName(Phase phase) {
    switch (phase) {
        case Phase::Cold: return "cold";
        case Phase::Warm: return "warm";
        case Phase::Reference: return "ref";
    }
    return "?";
}

std::optional<RayStats> readStatsJson(const fs::path& file) {
    // ray writes the file with nlohmann-json (render_stats.cpp); a missing key or a file
    // cut short by a killed run means no statistics.
    try {
        const nlohmann::json json = nlohmann::json::parse(readText(file));
        RayStats s;
        json.at("width").get_to(s.width);
        json.at("height").get_to(s.height);
        json.at("samples").get_to(s.samples);
        json.at("depth").get_to(s.depth);
        json.at("primary_rays").get_to(s.primaryRays);
        json.at("shadow_rays").get_to(s.shadowRays);
        json.at("secondary_rays").get_to(s.secondaryRays);
        json.at("total_rays").get_to(s.totalRays);
        json.at("load_seconds").get_to(s.loadSeconds);
        json.at("bvh_build_seconds").get_to(s.bvhBuildSeconds);
        json.at("kernel_build_seconds").get_to(s.kernelBuildSeconds);
        json.at("render_seconds").get_to(s.renderSeconds);
        json.at("mrays_per_second").get_to(s.mraysPerSecond);
        s.device = json.value("device", "");
        return s;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;
    }
}

RunRecord runRay(const RayInvocation& invocation, const BenchScene& scene, const BenchDevice& device,
                 Phase phase) {
    const std::string stem = fileStem(scene, device, phase);
    const fs::path statsFile = invocation.workDir / (stem + ".stats.json");
    const fs::path logFile = invocation.workDir / (stem + ".log");
    fs::remove(statsFile);

    ChildCommand command;
    command.argv = rayArguments(invocation, scene, device, statsFile);
    command.environment = cacheEnvironment(invocation.cacheDir);
    command.log = logFile;
    command.timeoutSeconds = invocation.timeoutSeconds;
    ChildOutcome outcome = runChild(command);

    RunRecord record{&scene, &device, phase, outcome.describe(), std::nullopt, outcome.wallSeconds,
                     outcome.peakMiB};
    if (outcome.succeeded()) {
        record.stats = readStatsJson(statsFile);
        if (!record.stats) record.status = "no statistics";
    }
    if (!record.ok() && !outcome.timedOut)
        std::cerr << "  " << stem << ": " << record.status << "; its output ends with:\n" << tailOf(logFile, 6);
    return record;
}

std::vector<BenchDevice> listOpenClDevices(const fs::path& rayBinary, const fs::path& workDir) {
    const fs::path listing = workDir / "devices.txt";
    ChildCommand command;
    command.argv = {rayBinary.string(), "--list-devices"};
    command.log = listing;
    command.timeoutSeconds = 60;
    ChildOutcome outcome = runChild(command);
    if (!outcome.succeeded()) {
        std::cerr << "ray_bench: `ray --list-devices` failed (" << outcome.describe()
                  << "); only the reference renderer will run\n" << tailOf(listing, 6);
        return {};
    }
    // Device lines are "N: name"; the indented lines under them describe it.
    static const std::regex deviceLine(R"(^(\d+): (.*)$)");
    std::vector<BenchDevice> devices;
    std::ifstream in(listing);
    for (std::string line; std::getline(in, line);) {
        std::smatch match;
        if (std::regex_match(line, match, deviceLine))
            devices.push_back({match[1].str(), "cl" + match[1].str(), match[2].str(), {}});
    }
    return devices;
}

}  // namespace bench
