// The one-pass reader of plain XML (scene/xml_plain_reader.h) against expat: on what it
// takes, the same tree, lines and spans; what it does not take it leaves to expat, whose
// tree or error XmlTree::parse then gives.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "scene/scene_loader.h"
#include "scene/xml_plain_reader.h"
#include "scene/xml_tree.h"
#include "scene_comparison.h"
#include "test_support.h"
#include "xml_pieces.h"

using ray::readPlainXml;
using ray::XmlElement;
using ray::XmlError;
using ray::XmlTree;
using ray::test::xmlInPieces;

namespace {

constexpr int kDepth = 100;

// Read by expat, fed 4 KiB at a time (XmlTree::parse of a source never takes the plain
// reader).
XmlTree parseWithExpat(const std::string& xml, bool spans, int maxDepth = kDepth) {
    return XmlTree::parse(xmlInPieces(xml, 4096), maxDepth, 0, spans);
}

// Everything a tree holds, element by element in document order: name, line, attributes,
// first child and next sibling, and the span when there is one.
std::string everything(const XmlTree& tree) {
    std::string text;
    for (uint32_t i = 0; i < tree.elementCount(); ++i) {
        const XmlElement e = tree.element(i);
        text += std::to_string(i) + ":" + e.name() + "@" + std::to_string(e.line());
        for (size_t a = 0; a < e.attributeCount(); ++a)
            text += std::string(" ") + e.attributeName(a) + "=[" + e.attributeValue(a) + "]";
        text += " child " + (e.firstChild() ? std::to_string(e.firstChild().index()) : std::string("-"));
        text += " next " + (e.nextSibling() ? std::to_string(e.nextSibling().index()) : std::string("-"));
        if (tree.hasSpans())
            text += " span " + std::to_string(e.span().begin) + "," + std::to_string(e.span().startTagEnd) + "," +
                    std::to_string(e.span().end);
        text += "\n";
    }
    return text;
}

// What XmlTree::parse of `xml` gives: its tree, or its error.
std::string outcome(const std::function<XmlTree()>& parse) {
    try {
        return everything(parse());
    } catch (const XmlError& e) {
        return "error " + std::to_string(int(e.kind)) + " line " + std::to_string(e.line) + ": " + e.what();
    }
}

// The plain reader takes `xml`, whole or fed in pieces down to a byte at a time, and gives
// expat's tree, with and without spans.
void checkReadAsExpatReadsIt(const std::string& xml) {
    INFO(xml);
    for (bool spans : {false, true}) {
        const std::string expat = everything(parseWithExpat(xml, spans));
        std::optional<XmlTree> plain = readPlainXml(xml, kDepth, spans);
        REQUIRE(plain);
        CHECK(plain->hasSpans() == spans);
        CHECK(everything(*plain) == expat);
        for (size_t piece : {1, 2, 3, 7, 64}) {
            INFO("pieces of " << piece);
            std::optional<XmlTree> streamed = readPlainXml(xmlInPieces(xml, piece), 0, kDepth, spans);
            REQUIRE(streamed);
            CHECK(everything(*streamed) == expat);
        }
    }
}

// A scene as the course writes them, and as the sphere scenes are generated.
const std::string kScene =
    "<scenefile>\n"
    "  <globaldata><ambientcoeff v=\"0.2\"/><diffusecoeff v=\"0.7\"/></globaldata>\n"
    "  <cameradata><pos x=\"13\" y=\"9\" z=\"17\"/><heightangle v=\"45\"/></cameradata>\n"
    "  <!-- lights -- two of them -->\n"
    "  <lightdata><id v=\"0\"/><type v=\"point\"/><color r=\"1\" g=\"1\" b=\"1\"/></lightdata>\n"
    "  <object type=\"tree\" name=\"root\">\n"
    "    <transblock><translate x=\"-3.65636\" y=\"3.47434\" z=\"2.63775\"/>"
    "<object type=\"primitive\" name=\"sphere\"><diffuse r=\"0.9\" g=\"0.2\" b=\"0.9\"/></object></transblock>\n"
    "    <transblock>\n      <scale x='0.1' y='0.1' z='0.1' />\n"
    "      <object type=\"primitive\" name=\"cube\"><texture file=\"image/board.png\" u=\"1\" v=\"1\"/></object>\n"
    "    </transblock >\n"
    "  </object>\n"
    "</scenefile>\n";

}  // namespace

TEST_CASE("plain XML reader: the same tree, lines and spans as expat", "[xml]") {
    checkReadAsExpatReadsIt(kScene);
    checkReadAsExpatReadsIt("<a/>");
    checkReadAsExpatReadsIt("<?xml version=\"1.0\"?>\n<a x=\"1\"/>");
    checkReadAsExpatReadsIt("<?xml version='1.0' encoding='utf-8' standalone='yes' ?>\n\n<a>\n<b/></a>");
    checkReadAsExpatReadsIt("\xEF\xBB\xBF<?xml version=\"1.0\" encoding=\"UTF-8\"?><a><b/></a>");  // a byte-order mark
    checkReadAsExpatReadsIt("\xEF\xBB\xBF\n<a/>");
    // Comments before, inside and after, "--" inside them taken as the loader takes it.
    checkReadAsExpatReadsIt("<!-- x -->\n<!---->\n<a><!-- --no-dof -- x --->\n<b/><!-- - -->\n<!-- <c/> --></a><!-- y -->");
    // Blanks inside tags, around '=', tabs and line breaks in values (read as blanks).
    checkReadAsExpatReadsIt("<a\n  x = '1'\n\ty=\"2\t3\n4\" >\n<b\nz=\"\"\n/></a\n>");
    // Line ends of Windows and old Macs: a line each, in tags and between them.
    checkReadAsExpatReadsIt("<a>\r\n<b x=\"1\"\r\n y=\"2\"/>\r\n\r\n<c/>\r<d/>\r\r\n<e/></a>\r\n");
    // Names with digits, dots, dashes and underscores; text between elements; what follows
    // the root's end tag ignored (as XmlTree::parse ignores it).
    checkReadAsExpatReadsIt("<_a.b-c d1_.-=\"v>w\">text, (1 > 0) <e9/> more</_a.b-c>\n<b/> junk & <");
}

TEST_CASE("plain XML reader: what it does not take, expat reads, with the same tree or error", "[xml]") {
    const std::vector<std::string> notPlain = {
        "",                                                     // empty
        " \n\t",                                              // blank
        "<!-- nothing -->",                                     // no element
        "text<a/>",                                             // text before the root
        "<a>\n<b>\n</a>\n",                                  // the wrong end tag
        "<a>\n<b>\n<c/>",                                     // the file ends first
        "<a>\n<pos x=1/>\n</a>",                              // no quotes
        "<a>\n<pos x=\"1\"y=\"2\"/></a>",                  // no blank between attributes
        "<a>\n\n<pos x=\"1\" x=\"2\"/></a>",              // an attribute twice
        "<a><t file=\"a&b.png\"/></a>",                       // a bare '&'
        "<a x=\"1 &amp; 2\" y=\"&#65;\">&lt;</a>",          // entities, read by expat
        "<a><![CDATA[ <b/> ]]><c/></a>",                        // CDATA
        "<!DOCTYPE a>\n<a/>",                                  // a DOCTYPE
        "<a><?pi x?><b/></a>",                                  // a processing instruction
        "  <?xml version=\"1.0\"?><a/>",                      // a declaration not first
        "<?xml version=\"1.1\"?><a/>",                        // XML 1.1
        "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><a v=\"\xE9\"/>",  // another encoding
        "<a v=\"caf\xC3\xA9\"/>",                           // UTF-8 beyond ASCII
        "<a>\n<!-- caf\xE9 --></a>",                          // not UTF-8
        "<a v=\"1\r\n2\"/>",                                // a carriage return in a value
        "<a><b v=\"<\"/></a>",                                // '<' in a value
        "<a>x ]]> y</a>",                                       // "]]>" in text
        "<a>\x01</a>",                                         // a control character
        "<a:b/>",                                               // a colon in a name
        "<a><!-- never closed </a>",                            // a comment not closed
        "<a></a ",                                              // an end tag not closed
    };
    for (const std::string& xml : notPlain) {
        INFO(xml);
        CHECK_FALSE(readPlainXml(xml, kDepth, false));
        CHECK_FALSE(readPlainXml(xmlInPieces(xml, 2), 0, kDepth, false));
        // XmlTree::parse gives what expat gives.
        for (bool spans : {false, true})
            CHECK(outcome([&] { return XmlTree::parse(xml, kDepth, spans); }) ==
                  outcome([&] { return parseWithExpat(xml, spans); }));
    }
    // Nesting past the limit: left to expat, which says how deep.
    const std::string nested = "<e>\n<e>\n<e/></e></e>";
    CHECK(readPlainXml(nested, 3, false));
    CHECK_FALSE(readPlainXml(nested, 2, false));
    CHECK(outcome([&] { return XmlTree::parse(nested, 2); }) == "error 3 line 3: elements nest more than 2 levels deep");
}

namespace {

// `text` with `edits` random edits: bytes replaced, inserted or removed, the bytes drawn
// from those that make XML's syntax, and a few that break it.
std::string mutated(std::string text, std::mt19937& random, int edits) {
    static const std::string kBytes = "<>/=\"'&;!-?[] \t\n\rax9:.#\xC3\x01";
    for (int i = 0; i < edits && !text.empty(); ++i) {
        const size_t at = std::uniform_int_distribution<size_t>(0, text.size() - 1)(random);
        const char byte = kBytes[std::uniform_int_distribution<size_t>(0, kBytes.size() - 1)(random)];
        switch (std::uniform_int_distribution<int>(0, 2)(random)) {
            case 0: text[at] = byte; break;
            case 1: text.insert(text.begin() + std::ptrdiff_t(at), byte); break;
            default: text.erase(at, 1); break;
        }
    }
    return text;
}

}  // namespace

TEST_CASE("plain XML reader: tags and comments longer than a piece read from a source", "[xml]") {
    // A value of 3 MB and a comment of 3 MB, past the window's 1 MB pieces, and many small
    // elements before them, so that they fall across the pieces' ends.
    std::string xml = "<a>\n";
    for (int i = 0; i < 40000; ++i) xml += "<b x=\"" + std::to_string(i) + "\"/>\r\n";
    xml += "<c v=\"" + std::string(3 << 20, 'v') + "\"/>\n<!--" + std::string(3 << 20, '-') + "-->\n<d/></a>";
    const std::string expat = everything(parseWithExpat(xml, true));
    for (size_t piece : {size_t(1) << 20, size_t(4096)}) {
        std::optional<XmlTree> streamed = readPlainXml(xmlInPieces(xml, piece), xml.size(), kDepth, true);
        REQUIRE(streamed);
        CHECK(everything(*streamed) == expat);
    }
}

TEST_CASE("plain XML reader: an element with thousands of attributes, one of them twice or not", "[xml]") {
    std::string attributes;
    for (int i = 0; i < 20000; ++i) attributes += " a" + std::to_string(i) + "=\"" + std::to_string(i) + "\"";
    checkReadAsExpatReadsIt("<a>\n<b" + attributes + "/></a>");
    const std::string twice = "<a>\n<b" + attributes + " a7=\"x\"/></a>";
    CHECK_FALSE(readPlainXml(twice, kDepth, false));
    CHECK(outcome([&] { return XmlTree::parse(twice, kDepth); }) ==
          "error 2 line 2: <b> has the same attribute twice");
}

TEST_CASE("plain XML reader: random edits of a scene read as expat reads them", "[xml]") {
    std::mt19937 random(51);
    int taken = 0;
    for (int round = 0; round < 3000; ++round) {
        const std::string xml = mutated(kScene, random, 1 + round % 3);
        std::optional<XmlTree> plain = readPlainXml(xml, kDepth, true);
        std::optional<XmlTree> streamed = readPlainXml(xmlInPieces(xml, 1 + size_t(round % 13)), 0, kDepth, true);
        CHECK(bool(streamed) == bool(plain));
        if (plain && streamed) CHECK(everything(*streamed) == everything(*plain));
        const std::string expat = outcome([&] { return parseWithExpat(xml, true); });
        if (plain) {
            ++taken;
            INFO(xml);
            CHECK(everything(*plain) == expat);  // never a text expat refuses, never another tree
        }
        CHECK(outcome([&] { return XmlTree::parse(xml, kDepth, true); }) == expat);
    }
    // Many edits fall in values, blanks and comments, where the text stays plain XML.
    CHECK(taken > 300);
}

TEST_CASE("plain XML reader: every course scene reads to expat's tree", "[xml][corpus]") {
    std::optional<std::filesystem::path> shared = ray::test::sharedDir();
    if (!shared) {
        ray::test::skip("../shared/cs123 is absent: the course corpus is not here");
        return;
    }
    const std::vector<std::filesystem::path> scenes = ray::test::courseScenes(*shared);
    REQUIRE(!scenes.empty());
    for (const std::filesystem::path& scene : scenes) {
        INFO(scene.string());
        std::ifstream in(scene, std::ios::binary);
        const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string expat = outcome([&] { return parseWithExpat(xml, true, ray::kMaxElementDepth); });
        std::optional<XmlTree> plain = readPlainXml(xml, ray::kMaxElementDepth, true);
        // The corpus is plain XML (no entity, CDATA or declaration): every file expat reads,
        // the plain reader reads too, to the same tree; a malformed one is left to expat.
        if (expat.rfind("error ", 0) == 0)
            CHECK_FALSE(plain);
        else
            CHECK((plain && everything(*plain) == expat));
        CHECK(outcome([&] { return XmlTree::parse(xml, ray::kMaxElementDepth, true); }) == expat);
    }
}

namespace {

// A flat scene of `spheres` spheres, about 200 bytes each, the last one's diffuse colour
// written as `lastDiffuse`.
std::string sphereScene(int spheres, const std::string& lastDiffuse) {
    std::string xml =
        "<scenefile>\n<cameradata><pos x=\"0\" y=\"0\" z=\"9\"/><focus x=\"0\" y=\"0\" z=\"0\"/>"
        "<up x=\"0\" y=\"1\" z=\"0\"/><heightangle v=\"45\"/></cameradata>\n<object type=\"tree\" name=\"root\">\n";
    for (int i = 0; i < spheres; ++i) {
        const std::string diffuse = i + 1 < spheres ? "r=\"0.9\" g=\"0.2\" b=\"0.9\"" : lastDiffuse;
        xml += "  <transblock><translate x=\"" + std::to_string(i % 97) + "\" y=\"" + std::to_string(i % 89) +
               "\" z=\"-3.5\"/><scale x=\"0.1\" y=\"0.1\" z=\"0.1\"/><object type=\"primitive\" "
               "name=\"sphere\"><diffuse " + diffuse + "/><shininess v=\"20\"/></object></transblock>\n";
    }
    return xml + "</object>\n</scenefile>\n";
}

}  // namespace

TEST_CASE("a scene file that is not plain XML is read again from its start by expat", "[xml][loader]") {
    const std::filesystem::path folder = ray::test::freshOutputFolder("xml_plain_reader", "files");
    // Over 3 MB, so that the plain reader has read pieces of it before it meets what is not
    // plain, near the end.
    const int spheres = 20000;
    ray::test::writeFileText(folder / "plain.xml", sphereScene(spheres, "r=\"0.5\" g=\"0.5\" b=\"0.5\""));
    ray::test::writeFileText(folder / "entity.xml", sphereScene(spheres, "r=\"0.5\" g=\"&#48;.5\" b=\"0.5\""));
    REQUIRE(std::filesystem::file_size(folder / "entity.xml") > (3 << 20));
    const ray::Scene plain = ray::loadScene(folder / "plain.xml", ray::test::quietLoadOptions());
    const ray::Scene entity = ray::loadScene(folder / "entity.xml", ray::test::quietLoadOptions());
    CHECK(plain.primitives.size() == size_t(spheres));
    CHECK(ray::test::sameTables(plain, entity));
    // An error there: expat's words, with the file and the line.
    ray::test::writeFileText(folder / "twice.xml", sphereScene(spheres, "r=\"0.5\" g=\"0.5\" g=\"0.5\""));
    CHECK_THROWS_WITH(ray::loadScene(folder / "twice.xml", ray::test::quietLoadOptions()),
                      (folder / "twice.xml").string() + ":" + std::to_string(spheres + 3) +
                          ": error: malformed XML: <diffuse> has the same attribute twice; fix the XML syntax at that line");
}
