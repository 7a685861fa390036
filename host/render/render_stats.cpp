#include "render/render_stats.h"

#include "core/atomic_file.h"

#include <cstdio>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace ray {

namespace {
std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else out += c;
    }
    return out + "\"";
}
}  // namespace

void printStats(const RenderStats& s, std::ostream& out) {
    char line[256];
    std::snprintf(line, sizeof line, "image        %d x %d, %d samples/pixel max, depth %d, on %s\n", s.width,
                  s.height, s.samples, s.depth, s.device.c_str());
    out << line;
    std::snprintf(line, sizeof line, "rays         %llu primary, %llu shadow, %llu secondary, %llu total\n",
                  (unsigned long long)s.primaryRays, (unsigned long long)s.shadowRays,
                  (unsigned long long)s.secondaryRays, (unsigned long long)s.totalRays());
    out << line;
    std::snprintf(line, sizeof line,
                  "time         load %.3f s, BVH build %.3f s, kernel build %.3f s, render %.3f s\n",
                  s.loadSeconds, s.bvhBuildSeconds, s.kernelBuildSeconds, s.renderSeconds);
    out << line;
    std::snprintf(line, sizeof line, "speed        %.2f Mrays/s\n", s.mraysPerSecond());
    out << line;
}

std::string statsToJson(const RenderStats& s) {
    std::ostringstream o;
    o.precision(9);
    o << "{\n"
      << "  \"width\": " << s.width << ",\n"
      << "  \"height\": " << s.height << ",\n"
      << "  \"samples\": " << s.samples << ",\n"
      << "  \"depth\": " << s.depth << ",\n"
      << "  \"device\": " << jsonString(s.device) << ",\n"
      << "  \"primary_rays\": " << s.primaryRays << ",\n"
      << "  \"shadow_rays\": " << s.shadowRays << ",\n"
      << "  \"secondary_rays\": " << s.secondaryRays << ",\n"
      << "  \"total_rays\": " << s.totalRays() << ",\n"
      << "  \"load_seconds\": " << s.loadSeconds << ",\n"
      << "  \"bvh_build_seconds\": " << s.bvhBuildSeconds << ",\n"
      << "  \"kernel_build_seconds\": " << s.kernelBuildSeconds << ",\n"
      << "  \"render_seconds\": " << s.renderSeconds << ",\n"
      << "  \"mrays_per_second\": " << s.mraysPerSecond() << "\n"
      << "}\n";
    return o.str();
}

void writeStatsJson(const RenderStats& stats, const std::filesystem::path& file) {
    writeFileAtomically(file, statsToJson(stats));
}

}  // namespace ray
