// A save is always readable (scene_document.h saveDocument): it writes only characters XML
// can hold (scene/xml_characters.h), in the file's own encoding (scene/text_encoding.h),
// and what it would write is read back before the file is replaced.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "scene/document_edits.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"
#include "scene/text_encoding.h"
#include "scene/xml_characters.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;

LoadOptions quiet() { return ray::test::quietLoadOptions(false); }

fs::path scratchFolder(const std::string& name) {
    const fs::path folder = test::outputDir() / ("document_encoding_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

std::string bytesOf(const fs::path& file) { return ray::test::fileText(file); }

void write(const fs::path& file, const std::string& bytes) { std::ofstream(file, std::ios::binary) << bytes; }

std::string utf16le(const std::string& ascii) {
    std::string out = "\xFF\xFE";
    for (char c : ascii) out += std::string{c, '\0'};
    return out;
}

// A tree of that name, holding nothing, made in code.
NamedTree emptyTree(const std::string& name) {
    NamedTree tree;
    tree.name = name;
    return tree;
}

PrimitiveNode& firstObject(SceneDocument& document) {
    PrimitiveNode* first = nullptr;
    forEachObject(document, [&](PrimitiveNode& node, const DocumentPlace&) {
        if (!first) first = &node;
    });
    REQUIRE(first);
    return *first;
}

const char* const kLatin1Scene =
    "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n"
    "<!-- caf\xE9: a comment in ISO-8859-1 -->\n"
    "<scenefile>\n"
    "  <object type=\"tree\" name=\"caf\xE9\">\n"
    "    <transblock><object type=\"primitive\" name=\"cube\"/></transblock>\n"
    "  </object>\n"
    "  <object type=\"tree\" name=\"root\">\n"
    "    <transblock><object type=\"master\" name=\"caf\xE9\"/></transblock>\n"
    "  </object>\n"
    "</scenefile>\n";

}  // namespace

TEST_CASE("XML's characters: U+FFFE, U+FFFF, C0 controls, surrogates and bytes not UTF-8 are found and named",
          "[document][encoding]") {
    CHECK_FALSE(firstUnwritableCharacter("caf\xC3\xA9 \xCE\xA9 \xF0\x9F\x99\x82\t\n\r"));
    auto found = [](const std::string& text) {
        const auto unwritable = firstUnwritableCharacter(text);
        REQUIRE(unwritable);
        return unwritableSentence("name", *unwritable);
    };
    CHECK(found("abc\xEF\xBF\xBF") == "name: U+FFFF at character 4 cannot be written in an XML file");
    CHECK(found("\xC3\xA9\xEF\xBF\xBE") == "name: U+FFFE at character 2 cannot be written in an XML file");
    CHECK(found(std::string("a\0b", 3)) == "name: U+0000 at character 2 cannot be written in an XML file");
    CHECK(found("a\x1B") == "name: U+001B at character 2 cannot be written in an XML file");
    CHECK(found("a\xED\xA0\x80") == "name: byte 0xED (not UTF-8) at character 2 cannot be written in an XML file");
    CHECK(found("ab\xC3") == "name: byte 0xC3 (not UTF-8) at character 3 cannot be written in an XML file");
    CHECK(found("\xC0\xAF") == "name: byte 0xC0 (not UTF-8) at character 1 cannot be written in an XML file");
    CHECK(characterCount("a\xC3\xA9\xF0\x9F\x99\x82") == 3);
    CHECK(firstCharacters("a\xC3\xA9\xC3\xA9", 2) == "a\xC3\xA9");
}

TEST_CASE("a name or texture file XML cannot hold is refused by the save, with a sentence, and the file kept",
          "[document][encoding]") {
    const fs::path folder = scratchFolder("unwritable");
    const fs::path file = folder / "scene.xml";
    const std::string original = "<scenefile><object type=\"tree\" name=\"root\"><transblock>"
                                 "<object type=\"primitive\" name=\"cube\"><texture file=\"a.png\"/></object>"
                                 "</transblock></object></scenefile>\n";
    write(file, original);
    Resources resources;

    SECTION("a tree's name") {
        SceneDocument document = loadSceneDocument(file, quiet());
        document.trees.emplace("ab\xEF\xBF\xBF", emptyTree("ab\xEF\xBF\xBF"));
        CHECK_THROWS_WITH(saveDocument(document, resources, file),
                          Catch::Matchers::Contains("U+FFFF at character 3 cannot be written in an XML file"));
    }
    SECTION("a texture file") {
        SceneDocument document = loadSceneDocument(file, quiet());
        firstObject(document).files->missingTexture = "b\xEF\xBF\xBE.png";
        CHECK_THROWS_WITH(saveDocument(document, resources, file),
                          Catch::Matchers::Contains("texture file 'b") &&
                              Catch::Matchers::Contains("U+FFFE at character 2 cannot be written in an XML file"));
    }
    CHECK(bytesOf(file) == original);
}

TEST_CASE("a save that would not load is refused with the loader's reason, and the file kept", "[document][encoding]") {
    const fs::path folder = scratchFolder("reread");
    const fs::path file = folder / "scene.xml";
    const std::string original = "<scenefile><object type=\"tree\" name=\"root\"><transblock>"
                                 "<object type=\"primitive\" name=\"cube\"/></transblock></object></scenefile>\n";
    write(file, original);
    SceneDocument document = loadSceneDocument(file, quiet());
    Resources resources;
    firstObject(document).material.shininess = -1;  // past the edits' rules: the loader refuses it
    try {
        saveDocument(document, resources, file);
        FAIL("saved");
    } catch (const InputError& e) {
        const std::string why = e.what();
        CHECK_THAT(why, Catch::Matchers::Contains("not saved") && Catch::Matchers::Contains("kept as it was") &&
                            Catch::Matchers::Contains("would not load") && Catch::Matchers::Contains("shininess"));
    }
    CHECK(bytesOf(file) == original);
    CHECK_FALSE(fs::exists(folder / "other.xml"));
    CHECK_THROWS_AS(saveDocument(document, resources, folder / "other.xml"), InputError);
    CHECK_FALSE(fs::exists(folder / "other.xml"));
}

TEST_CASE("an ISO-8859-1 scene stays ISO-8859-1: unedited byte for byte, edited with its text and comments",
          "[document][encoding]") {
    const fs::path folder = scratchFolder("latin1");
    const fs::path file = folder / "scene.xml";
    write(file, kLatin1Scene);
    SceneDocument document = loadSceneDocument(file, quiet());
    REQUIRE(document.source);
    CHECK(document.source->encoding() == TextEncoding::Latin1);
    CHECK(document.trees.count("caf\xC3\xA9") == 1);  // read as UTF-8
    Resources resources;
    saveDocument(document, resources, file);
    CHECK(bytesOf(file) == kLatin1Scene);

    // A name within ISO-8859-1 is written as its byte; one beyond it as a reference.
    renameTree(document, "caf\xC3\xA9", "\xCE\xA9mega \xC3\xBC");
    firstObject(document).material.shininess = 7;
    saveDocument(document, resources, file);
    const std::string saved = bytesOf(file);
    CHECK(saved.find("<!-- caf\xE9: a comment in ISO-8859-1 -->") != std::string::npos);
    CHECK(saved.find("name=\"&#x3A9;mega \xFC\"") != std::string::npos);
    CHECK(saved.find("\xC3") == std::string::npos);  // no UTF-8 in it
    CHECK(saved.rfind("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n", 0) == 0);
    SceneDocument reloaded = loadSceneDocument(file, quiet());
    CHECK(reloaded.trees.count("\xCE\xA9mega \xC3\xBC") == 1);
    CHECK(firstObject(reloaded).material.shininess == 7);
    CHECK(documentFileBytes(reloaded, resources, file) == saved);
}

TEST_CASE("a UTF-16 scene with a byte-order mark stays UTF-16: unedited byte for byte, edited with its comments",
          "[document][encoding]") {
    const fs::path folder = scratchFolder("utf16");
    const fs::path file = folder / "scene.xml";
    const std::string original = utf16le(
        "<?xml version=\"1.0\" encoding=\"UTF-16\"?>\r\n<!-- kept -->\r\n<scenefile>\r\n"
        "  <object type=\"tree\" name=\"root\">\r\n"
        "    <transblock><object type=\"primitive\" name=\"cube\"/></transblock>\r\n"
        "  </object>\r\n</scenefile>\r\n");
    write(file, original);
    SceneDocument document = loadSceneDocument(file, quiet());
    REQUIRE(document.source);
    CHECK(document.source->encoding() == TextEncoding::Utf16LE);
    Resources resources;
    saveDocument(document, resources, file);
    CHECK(bytesOf(file) == original);

    firstObject(document).material.diffuse = {0.25, 0.5, 1};
    saveDocument(document, resources, file);
    const std::string saved = bytesOf(file);
    CHECK(saved.rfind("\xFF\xFE<\0?\0x\0m\0l\0", 0) == 0);
    CHECK(toUtf8(saved, TextEncoding::Utf16LE) ==
          toUtf8(utf16le("<?xml version=\"1.0\" encoding=\"UTF-16\"?>\r\n<!-- kept -->\r\n<scenefile>\r\n"
                         "  <object type=\"tree\" name=\"root\">\r\n"
                         "    <transblock><object type=\"primitive\" name=\"cube\">\r\n"
                         "  <diffuse r=\"0.25\" g=\"0.5\" b=\"1\"/>\r\n"
                         "</object></transblock>\r\n"
                         "  </object>\r\n</scenefile>\r\n"),
                 TextEncoding::Utf16LE));
    SceneDocument reloaded = loadSceneDocument(file, quiet());
    CHECK(firstObject(reloaded).material.diffuse == Vec3{0.25, 0.5, 1});
}

TEST_CASE("a UTF-16 scene's names beyond the BMP go through the save as themselves", "[document][encoding]") {
    const fs::path folder = scratchFolder("utf16_names");
    const fs::path file = folder / "scene.xml";
    std::string original = utf16le("<scenefile><object type=\"tree\" name=\"root\"><transblock>"
                                   "<object type=\"primitive\" name=\"cube\"/></transblock></object></scenefile>");
    write(file, original);
    SceneDocument document = loadSceneDocument(file, quiet());
    document.trees.emplace("\xF0\x9F\x99\x82", emptyTree("\xF0\x9F\x99\x82"));
    Resources resources;
    saveDocument(document, resources, file);
    const std::string saved = bytesOf(file);
    CHECK(saved.find(std::string("\x3D\xD8\x42\xDE", 4)) != std::string::npos);  // U+1F642 as a surrogate pair
    CHECK(loadSceneDocument(file, quiet()).trees.count("\xF0\x9F\x99\x82") == 1);
}

TEST_CASE("a US-ASCII scene stays ASCII: a name beyond it is written as a character reference",
          "[document][encoding]") {
    const fs::path folder = scratchFolder("ascii");
    const fs::path file = folder / "scene.xml";
    const std::string original = "<?xml version='1.0' encoding='us-ascii'?>\n"
                                 "<scenefile><object type=\"tree\" name=\"leg\"><transblock>"
                                 "<object type=\"primitive\" name=\"cube\"/></transblock></object>"
                                 "<object type=\"tree\" name=\"root\"><transblock><object type=\"master\" "
                                 "name=\"leg\"/></transblock></object></scenefile>\n";
    write(file, original);
    SceneDocument document = loadSceneDocument(file, quiet());
    REQUIRE(document.source);
    CHECK(document.source->encoding() == TextEncoding::Ascii);
    renameTree(document, "leg", "caf\xC3\xA9 \xF0\x9F\x99\x82");
    Resources resources;
    saveDocument(document, resources, file);
    const std::string saved = bytesOf(file);
    CHECK(saved.find("name=\"caf&#xE9; &#x1F642;\"") != std::string::npos);
    CHECK(std::all_of(saved.begin(), saved.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; }));
    CHECK(loadSceneDocument(file, quiet()).trees.count("caf\xC3\xA9 \xF0\x9F\x99\x82") == 1);
}
