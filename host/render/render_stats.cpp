#include "render/render_stats.h"

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
    // Several devices (or ranks): each one's share of the frame.
    if (s.devices.size() < 2) return;
    for (size_t i = 0; i < s.devices.size(); ++i) {
        const DeviceStats& d = s.devices[i];
        std::string who = i < s.deviceRanks.size() ? "rank " + std::to_string(s.deviceRanks[i]) + " " : "";
        std::snprintf(line, sizeof line, "device       %s%s: %d tiles, %llu pixels, %llu rays, busy %.3f s, %.2f Mrays/s%s\n",
                      who.c_str(), d.device.c_str(), d.tiles, (unsigned long long)d.pixels, (unsigned long long)d.rays,
                      d.busySeconds, d.mraysPerSecond(), d.failed ? " (failed, dropped)" : "");
        out << line;
    }
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
      << "  \"upload_seconds\": " << s.uploadSeconds << ",\n"
      << "  \"mrays_per_second\": " << s.mraysPerSecond() << ",\n"
      << "  \"devices\": [";
    for (size_t i = 0; i < s.devices.size(); ++i) {
        const DeviceStats& d = s.devices[i];
        o << (i ? "," : "") << "\n    {\"device\": " << jsonString(d.device);
        if (i < s.deviceRanks.size()) o << ", \"rank\": " << s.deviceRanks[i];
        o << ", \"tiles\": " << d.tiles << ", \"pixels\": " << d.pixels << ", \"rays\": " << d.rays
          << ", \"busy_seconds\": " << d.busySeconds << ", \"mrays_per_second\": " << d.mraysPerSecond()
          << ", \"failed\": " << (d.failed ? "true" : "false") << "}";
    }
    o << (s.devices.empty() ? "" : "\n  ") << "]\n}\n";
    return o.str();
}

void writeStatsJson(const RenderStats& stats, const std::filesystem::path& file) {
    std::filesystem::path tmp = file;
    tmp += ".tmp" + std::to_string(getpid());
    {
        std::ofstream out(tmp);
        out << statsToJson(stats);
        if (!out) throw std::runtime_error(file.string() + ": cannot write statistics");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error(file.string() + ": cannot write statistics: " + ec.message());
    }
}

}  // namespace ray
