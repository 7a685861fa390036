// `ray convert IN OUT` (app/convert_command.h): both directions, the format by OUT's
// extension, and every refusal: exit status 2, a sentence saying what is wrong, nothing
// written (an existing OUT left as it was).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "course_json_rules.h"
#include "scene/json_writer.h"
#include "scene/scene_loader.h"
#include "scene_comparison.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

LoadOptions quiet() { return ray::test::quietLoadOptions(); }

fs::path outputFolder(const std::string& name) { return ray::test::freshOutputFolder("convert_command", name); }

std::string readFile(const fs::path& file) { return ray::test::fileText(file); }

void writeFile(const fs::path& file, const std::string& text) { ray::test::writeFileText(file, text); }

// A scene of a light and `root` as its root tree's body; the body's first line is line 7.
std::string sceneWith(const std::string& root) {
    return R"(<scenefile>
  <globaldata><ambientcoeff v="0.5"/><diffusecoeff v="0.5"/><specularcoeff v="0.5"/></globaldata>
  <cameradata><pos x="0" y="0" z="5"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/><heightangle v="45"/></cameradata>
  <lightdata><id v="0"/><color r="1" g="1" b="1"/><position x="1" y="2" z="3"/></lightdata>
  <object type="tree" name="root">
)" + root + "\n  </object>\n</scenefile>\n";
}

}  // namespace

TEST_CASE("ray convert: XML to JSON and back, the format by the output's extension", "[convert][cli]") {
    const fs::path folder = outputFolder("both_ways") / "scenes";
    fs::create_directories(folder);
    const std::string xml = sceneWith(R"(    <transblock><scale x="2" y="1" z="1"/><translate x="0" y="1" z="0"/>
      <object type="primitive" name="sphere"><diffuse r="0.5" g="0.5" b="1"/></object></transblock>)");
    writeFile(folder / "in.xml", xml);
    auto result = ray::test::runRay({"convert", (folder / "in.xml").string(), (folder / "out.json").string()});
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    CHECK_THAT(result.output, Contains("wrote"));
    const std::string json = readFile(folder / "out.json");
    SceneDocument document = loadSceneDocumentFromText(xml, folder / "in.xml", quiet());
    CHECK(json == documentToJson(document, Resources{}, folder / "out.json"));
    CHECK_THAT(json, Contains(R"("scale": [2, 1, 1],
      "groups": [
        {
          "translate": [0, 1, 0],)"));
    CHECK(ray::test::CourseJsonRules::breaches(json).empty());

    auto back = ray::test::runRay({"convert", (folder / "out.json").string(), (folder / "back.XML").string()});
    INFO(back.output);
    REQUIRE(back.exitCode == 0);
    CHECK_THAT(readFile(folder / "back.XML"), StartsWith("<scenefile>"));
    Scene original = loadSceneFromText(xml, folder / "in.xml", quiet());
    Scene roundTripped = loadScene(folder / "back.XML", quiet());
    CHECK(ray::test::sameTables(original, roundTripped));
    REQUIRE(roundTripped.primitives.size() == 1);
    // Nested groups compose in another order than the block's one product: the same place.
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            CHECK(roundTripped.primitives[0].objectToWorld.m[r][c] ==
                  Approx(original.primitives[0].objectToWorld.m[r][c]).margin(1e-15));
}

TEST_CASE("ray convert refuses bad input with exit status 2 and writes nothing", "[convert][cli]") {
    const fs::path folder = outputFolder("refusals");
    const fs::path in = folder / "in.xml", torus = folder / "torus.xml", out = folder / "out.json";
    writeFile(in, sceneWith(""));
    writeFile(torus, sceneWith(R"(    <transblock>
      <object type="primitive" name="torus"/>
    </transblock>)"));
    auto refused = [&](const std::vector<std::string>& args, const std::string& says) {
        auto result = ray::test::runRay(args);
        INFO(result.output);
        CHECK(result.exitCode == 2);
        CHECK_THAT(result.output, Contains(says));
        CHECK_FALSE(fs::exists(out));
    };
    refused({"convert", torus.string(), out.string()}, "torus.xml:7: error: a torus cannot be written");
    refused({"convert"}, "no scene file given");
    refused({"convert", in.string()}, "no output file given");
    refused({"convert", in.string(), out.string(), "extra"}, "too many arguments");
    refused({"convert", in.string(), (folder / "out.txt").string()}, "name it .json (the course's JSON) or .xml");
    refused({"convert", in.string(), (folder / "copy.xml").string()}, "is already CS123 XML: nothing to convert");
    CHECK_FALSE(fs::exists(folder / "copy.xml"));
    refused({"convert", (folder / "missing.xml").string(), out.string()}, "missing.xml");
    refused({"convert", in.string(), out.string(), "--no-such-option"}, "--no-such-option");
    writeFile(folder / "broken.json", "{\"globalData\": {\"ambientCoeff\": 1}");
    refused({"convert", (folder / "broken.json").string(), (folder / "broken.xml").string()}, "broken.json:1:");
    CHECK_FALSE(fs::exists(folder / "broken.xml"));
    // Found only when flattened: refused in the input's terms.
    writeFile(folder / "cycle.xml", sceneWith(R"(    <transblock><object type="master" name="a"/></transblock>
  </object>
  <object type="tree" name="a"><transblock><object type="master" name="a"/></transblock>)"));
    refused({"convert", (folder / "cycle.xml").string(), out.string()}, "cycle.xml:");

    SECTION("an output that is the input, through a link, is refused and the input kept") {
        fs::create_symlink(in, folder / "link.json");
        auto result = ray::test::runRay({"convert", in.string(), (folder / "link.json").string()});
        INFO(result.output);
        CHECK(result.exitCode == 2);
        CHECK_THAT(result.output, Contains("is the scene to convert"));
        CHECK(readFile(in) == sceneWith(""));
    }
    SECTION("an existing output is left as it was when the input is refused") {
        writeFile(out, "kept");
        auto result = ray::test::runRay({"convert", torus.string(), out.string()});
        CHECK(result.exitCode == 2);
        CHECK(readFile(out) == "kept");
        fs::remove(out);
    }
    SECTION("a read-only output is refused unless --replace-read-only says to replace it") {
        const fs::path kept = folder / "kept.json";
        writeFile(kept, "kept");
        fs::permissions(kept, fs::perms::owner_read);
        auto result = ray::test::runRay({"convert", in.string(), kept.string()});
        INFO(result.output);
        CHECK(result.exitCode == 2);
        CHECK_THAT(result.output, Contains("is read-only"));
        CHECK(readFile(kept) == "kept");
        auto replaced = ray::test::runRay({"convert", in.string(), kept.string(), "--replace-read-only"});
        CHECK(replaced.exitCode == 0);
        CHECK_THAT(readFile(kept), StartsWith("{"));
    }
}

TEST_CASE("ray convert --help says what it does, and ray --help lists it", "[convert][cli]") {
    auto help = ray::test::runRay({"convert", "--help"});
    CHECK(help.exitCode == 0);
    CHECK_THAT(help.output, StartsWith("usage: ray convert <in> <out> [options]"));
    auto all = ray::test::runRay({"--help"});
    CHECK_THAT(all.output, Contains("  ray convert <in> <out> [options]"));
}
