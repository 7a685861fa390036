// Which OpenCL devices ray takes (host/opencl/opencl_device.h) and what it says when there
// is none, through the ray command with a vendors folder of the test's own: the ICD loader
// reads $OCL_ICD_VENDORS instead of /etc/OpenCL/vendors, so each case sees only the
// platforms it names, in an order it does not control (readdir).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "opencl/opencl_device.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using ray::test::runRay;

const fs::path kSystemVendors = "/etc/OpenCL/vendors";

// A vendors folder holding the system's ICD files `icds` under the names `as` (the same
// names when empty), or nothing when one of them is not installed.
std::optional<fs::path> vendorsFolder(const std::string& name, const std::vector<std::string>& icds,
                                      std::vector<std::string> as = {}) {
    if (as.empty()) as = icds;
    fs::path folder = ray::test::outputDir() / "opencl_vendors" / name;
    fs::remove_all(folder);
    fs::create_directories(folder);
    for (size_t i = 0; i < icds.size(); ++i) {
        if (!fs::exists(kSystemVendors / icds[i])) return std::nullopt;
        fs::copy_file(kSystemVendors / icds[i], folder / as[i]);
    }
    return folder;
}

std::string scene(const std::string& name) { return (ray::test::scenesDir() / name).string(); }

// A small render's --stats-json with the devices of `selection`, or the failed run.
struct Render {
    ray::test::CommandResult run;
    std::string json;
};

Render renderWith(const fs::path& vendors, const std::string& selection, const std::vector<std::string>& env = {}) {
    fs::path out = ray::test::outputDir() / "opencl_vendors" / "out";
    fs::create_directories(out);
    fs::path json = out / ("stats_" + selection + ".json");
    fs::remove(json);
    std::vector<std::string> environment{"OCL_ICD_VENDORS=" + vendors.string()};
    environment.insert(environment.end(), env.begin(), env.end());
    Render r;
    r.run = runRay({scene("shadows.xml"), "16", "12", "--device", selection, "--quiet", "-o",
                    (out / ("x_" + selection + ".png")).string(), "--stats-json", json.string()},
                   300, environment);
    std::ifstream in(json);
    r.json.assign(std::istreambuf_iterator<char>(in), {});
    return r;
}

}  // namespace

TEST_CASE("a platform that lists no device is named, and only PoCL gets PoCL's cache hint", "[opencl][cli]") {
    // Mesa's two platforms, clover (mesa.icd) and rusticl, list no device on a machine without
    // a GPU they drive (rusticl lists llvmpipe only with RUSTICL_ENABLE=llvmpipe).
    for (const auto& [icd, platform] : {std::pair<std::string, std::string>{"rusticl.icd", "rusticl"},
                                        std::pair<std::string, std::string>{"mesa.icd", "Clover"}}) {
        auto vendors = vendorsFolder("only_" + icd, {icd});
        if (!vendors) {
            ray::test::skip(icd + " is not installed (Debian: mesa-opencl-icd)");
            continue;
        }
        Render r = renderWith(*vendors, "auto");
        INFO(r.run.output);
        CHECK(r.run.exitCode == 3);
        CHECK_THAT(r.run.output, Contains(platform));
        CHECK_THAT(r.run.output, Contains("--device ref"));
        CHECK_THAT(r.run.output, !Contains("POCL_CACHE_DIR"));
        auto list = runRay({"--list-devices"}, 60, {"OCL_ICD_VENDORS=" + vendors->string()});
        CHECK_THAT(list.output, Contains(platform));
    }
}

TEST_CASE("PoCL that cannot start is named with its cache hint", "[opencl][cli]") {
    auto vendors = vendorsFolder("pocl_broken", {"pocl.icd"});
    if (!vendors) return ray::test::skip("pocl.icd is not installed");
    // PoCL refuses to start when its cache folder cannot be made: here, below a file.
    fs::path file = ray::test::outputDir() / "opencl_vendors" / "not_a_folder";
    std::ofstream(file) << "x";
    Render r = renderWith(*vendors, "auto", {"POCL_CACHE_DIR=" + (file / "pocl").string()});
    INFO(r.run.output);
    CHECK(r.run.exitCode == 3);
    CHECK_THAT(r.run.output, Contains("PoCL"));
    CHECK_THAT(r.run.output, Contains("POCL_CACHE_DIR"));
}

TEST_CASE("auto, cpu and all take PoCL and never llvmpipe, which is listed with its cap", "[opencl][cli]") {
    auto vendors = vendorsFolder("pocl_and_llvmpipe", {"pocl.icd", "rusticl.icd"});
    if (!vendors) return ray::test::skip("pocl.icd or rusticl.icd (mesa-opencl-icd) is not installed");
    const std::vector<std::string> llvmpipe{"RUSTICL_ENABLE=llvmpipe"};
    auto list = runRay({"--list-devices"}, 60, {"OCL_ICD_VENDORS=" + vendors->string(), llvmpipe[0]});
    INFO(list.output);
    REQUIRE(list.exitCode == 0);
    if (list.output.find("llvmpipe") == std::string::npos) return ray::test::skip("rusticl lists no llvmpipe here");
    CHECK_THAT(list.output, Contains("65,535"));
    for (const std::string selection : {"auto", "cpu", "all"}) {
        Render r = renderWith(*vendors, selection, llvmpipe);
        INFO(selection << ": " << r.run.output);
        REQUIRE(r.run.exitCode == 0);
        CHECK_THAT(r.json, Contains("Portable Computing Language"));
        CHECK_THAT(r.json, !Contains("llvmpipe"));
    }
}

TEST_CASE("llvmpipe alone is not taken by itself, and the message says how to choose it", "[opencl][cli]") {
    auto vendors = vendorsFolder("only_llvmpipe", {"rusticl.icd"});
    if (!vendors) return ray::test::skip("rusticl.icd (mesa-opencl-icd) is not installed");
    for (const std::string selection : {"auto", "cpu", "all"}) {
        Render r = renderWith(*vendors, selection, {"RUSTICL_ENABLE=llvmpipe"});
        INFO(selection << ": " << r.run.output);
        if (r.run.output.find("llvmpipe") == std::string::npos) return ray::test::skip("rusticl lists no llvmpipe here");
        CHECK(r.run.exitCode == 3);
        CHECK_THAT(r.run.output, Contains("--device 0"));
        CHECK_THAT(r.run.output, Contains("65,535"));
        CHECK_THAT(r.run.output, !Contains("POCL_CACHE_DIR"));
    }
}

TEST_CASE("the device list does not depend on the order of the ICD files", "[opencl][cli]") {
    // The same two platforms under names that sort the other way round.
    auto first = vendorsFolder("order_a", {"pocl.icd", "rusticl.icd"}, {"a.icd", "b.icd"});
    auto second = vendorsFolder("order_b", {"pocl.icd", "rusticl.icd"}, {"b.icd", "a.icd"});
    if (!first || !second) return ray::test::skip("pocl.icd or rusticl.icd (mesa-opencl-icd) is not installed");
    auto a = runRay({"--list-devices"}, 60, {"OCL_ICD_VENDORS=" + first->string(), "RUSTICL_ENABLE=llvmpipe"});
    auto b = runRay({"--list-devices"}, 60, {"OCL_ICD_VENDORS=" + second->string(), "RUSTICL_ENABLE=llvmpipe"});
    INFO(a.output << "\n---\n" << b.output);
    CHECK(a.exitCode == 0);
    CHECK(a.output == b.output);
}

TEST_CASE("a missing GPU is a message naming the devices there are", "[opencl][cli]") {
    auto vendors = vendorsFolder("pocl_only", {"pocl.icd"});
    if (!vendors) return ray::test::skip("pocl.icd is not installed");
    Render r = renderWith(*vendors, "gpu");
    INFO(r.run.output);
    CHECK(r.run.exitCode == 3);
    CHECK_THAT(r.run.output, Contains("no OpenCL GPU device"));
    CHECK_THAT(r.run.output, Contains("Portable Computing Language"));
}

TEST_CASE("llvmpipe chosen by index comes with a warning about its cap", "[opencl]") {
    ray::OpenClDevice pipe;
    pipe.index = 3;
    pipe.name = "llvmpipe (LLVM 15.0.6, 256 bits)";
    pipe.platformName = "rusticl";
    pipe.isCpu = pipe.isLlvmpipe = true;
    std::string warning = ray::llvmpipeWarning(pipe);
    CHECK_THAT(warning, Contains("device 3"));
    CHECK_THAT(warning, Contains("65,535"));
    ray::OpenClDevice pocl = pipe;
    pocl.isLlvmpipe = false;
    CHECK(ray::llvmpipeWarning(pocl).empty());
}
