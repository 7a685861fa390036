// The XML tree under the scene loader (scene/xml_tree.h): layout, errors, limits, and the
// pieces it is fed in, down to one byte at a time.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "scene/xml_tree.h"
#include "xml_pieces.h"

using Catch::Matchers::Contains;
using ray::XmlElement;
using ray::XmlError;
using ray::XmlTree;

namespace {

constexpr int kDepth = 100;

// Parses `xml` handed over `piece` bytes at a time.
XmlTree parseInPieces(const std::string& xml, size_t piece, int maxDepth = kDepth) {
    return XmlTree::parse(ray::test::xmlInPieces(xml, piece), maxDepth);
}

// The tree written back as text: names, attributes and lines, children nested.
std::string dump(XmlElement element) {
    std::string text = std::string(element.name()) + "@" + std::to_string(element.line());
    for (size_t i = 0; i < element.attributeCount(); ++i)
        text += std::string(" ") + element.attributeName(i) + "=" + element.attributeValue(i);
    std::string children;
    for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) children += dump(child);
    return children.empty() ? "(" + text + ")" : "(" + text + " " + children + ")";
}

// The same tree whatever the pieces: whole, one byte at a time, and a few sizes between.
std::string dumpEveryWay(const std::string& xml) {
    const std::string whole = dump(XmlTree::parse(xml, kDepth).root());
    for (size_t piece : {1, 2, 3, 5, 7, 11})
        CHECK(dump(parseInPieces(xml, piece).root()) == whole);
    return whole;
}

struct Failure {
    XmlError::Kind kind = XmlError::Kind::Malformed;
    int line = -1;
    std::string message;
};

Failure failureOf(const std::string& xml, int maxDepth = kDepth) {
    Failure failure;
    try {
        XmlTree::parse(xml, maxDepth);
    } catch (const XmlError& e) {
        failure = {e.kind, e.line, e.what()};
    }
    // Fed a byte at a time, the same error.
    try {
        parseInPieces(xml, 1, maxDepth);
        FAIL("parsed a byte at a time: " + xml);
    } catch (const XmlError& e) {
        CHECK(e.kind == failure.kind);
        CHECK(e.line == failure.line);
        CHECK(std::string(e.what()) == failure.message);
    }
    return failure;
}

}  // namespace

TEST_CASE("XML tree: elements, attributes in order, lines, siblings", "[loader][xml]") {
    const std::string xml = "<?xml version=\"1.0\"?>\n<a x=\"1\" y='2 &amp; 3'>\n  <b/>text<c z=\"&#65;\">\n<d/></c>\n"
                            "<!-- a comment -->\n<b q=\"\"/></a>\n";
    CHECK(dumpEveryWay(xml) == "(a@2 x=1 y=2 & 3 (b@3)(c@3 z=A (d@4))(b@6 q=))");
    XmlTree tree = XmlTree::parse(xml, kDepth);
    CHECK(tree.elementCount() == 5);
    CHECK(tree.attributeCount() == 4);
    // Names are stored once: both <b> share one string.
    XmlElement first = tree.root().firstChild(), last = first.nextSibling().nextSibling();
    CHECK(first.name() == last.name());
    CHECK_FALSE(last.nextSibling());
    CHECK_FALSE(first.firstChild());
    tree.clear();
    CHECK_FALSE(tree.root());
}

TEST_CASE("XML tree: what follows the root element is ignored", "[loader][xml]") {
    CHECK(dumpEveryWay("<a/>\n<b/> junk & <") == "(a@1)");
}

TEST_CASE("XML tree: \"--\" inside comments is taken, as tinyxml2 took it", "[loader][xml]") {
    CHECK(dumpEveryWay("<a><!-- --no-dof -- x --->\n<b/><!----><!-- - -->\n<!-- <c/> --></a>") == "(a@1 (b@2))");
    // Outside comments nothing changes: in values, CDATA and processing instructions.
    CHECK(dumpEveryWay("<a v=\"--1 -->\"><![CDATA[ <!-- ]]><b w=\"-- x\"/><?pi <!-- ?><c/></a>") ==
          "(a@1 v=--1 --> (b@1 w=-- x)(c@1))");
    // After a DOCTYPE (whose entity values may quote "<!--") comments must be plain XML.
    CHECK(failureOf("<!DOCTYPE a>\n<a><!-- x -- y --></a>").line == 2);
}

TEST_CASE("XML tree: syntax errors name the element and the line", "[loader][xml]") {
    Failure unclosed = failureOf("<a>\n<b>\n</a>\n");
    CHECK(unclosed.kind == XmlError::Kind::Malformed);
    CHECK(unclosed.line == 2);
    CHECK(unclosed.message == "<b> is not closed (the end tag on line 3 closes another element)");

    Failure truncated = failureOf("<a>\n<b>\n<c/>");
    CHECK(truncated.line == 2);
    CHECK(truncated.message == "<b> is not closed (the file ends first)");

    Failure unquoted = failureOf("<a>\n<pos x=1/>\n</a>");
    CHECK(unquoted.line == 2);
    CHECK_THAT(unquoted.message, Contains("an attribute of <pos> is malformed (values need quotes"));
    CHECK_THAT(failureOf("<a>\n<pos x=\"1\"y=\"2\"/></a>").message, Contains("an attribute of <pos> is malformed"));

    Failure twice = failureOf("<a>\n\n<pos x=\"1\" x=\"2\"/></a>");
    CHECK(twice.line == 3);
    CHECK(twice.message == "<pos> has the same attribute twice");

    CHECK(failureOf("<a><t file=\"a&b.png\"/></a>").message == "an attribute of <t> has a bare '&' (write & as &amp;)");
    CHECK_THAT(failureOf("<a><t file=\"&nbsp;\"/></a>").message, Contains("an attribute of <t> has a bad entity"));
    CHECK(failureOf("<a><b></c></a>").message == "<b> is not closed (the end tag on line 1 closes another element)");
    CHECK(failureOf("  <?xml version=\"1.0\"?><a/>").message ==
          "the <?xml ...?> declaration is not at the very start of the file");
    CHECK(failureOf("text<a/>").line == 1);
}

TEST_CASE("XML tree: empty, element-less and non-UTF-8 texts", "[loader][xml]") {
    CHECK(failureOf("").kind == XmlError::Kind::Empty);
    CHECK(failureOf(" \n\t\n").kind == XmlError::Kind::Empty);
    CHECK(failureOf("<!-- nothing -->").kind == XmlError::Kind::NoElement);
    Failure latin1 = failureOf("<a>\n<!-- caf\xE9 --></a>");
    CHECK(latin1.line == 2);
    CHECK_THAT(latin1.message, Contains("byte 0xE9 is not UTF-8"));
    // Declared, it reads.
    CHECK(dump(XmlTree::parse("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><a v=\"\xE9\"/>", kDepth).root()) ==
          "(a@1 v=\xC3\xA9)");
}

TEST_CASE("XML tree: nesting past the limit is refused, at the limit it is not", "[loader][xml]") {
    auto nested = [](int depth) {
        std::string xml;
        for (int i = 0; i < depth; ++i) xml += "<e>\n";
        for (int i = 0; i < depth; ++i) xml += "</e>";
        return xml;
    };
    CHECK(XmlTree::parse(nested(50), 50).elementCount() == 50);
    Failure deep = failureOf(nested(51), 50);
    CHECK(deep.kind == XmlError::Kind::TooDeep);
    CHECK(deep.line == 51);
    CHECK(deep.message == "elements nest more than 50 levels deep");
    // Deep beyond any stack (the tree is built without recursion).
    CHECK(failureOf(nested(200000), 1000).kind == XmlError::Kind::TooDeep);
}

TEST_CASE("XML tree: external entities are not read, entity bombs are refused", "[loader][xml]") {
    // An external entity would read /etc/hostname into the value; it is an error instead.
    Failure external = failureOf("<!DOCTYPE a [<!ENTITY x SYSTEM \"/etc/hostname\">]>\n<a v=\"&x;\"/>");
    CHECK(external.line == 2);
    CHECK_THAT(external.message, Contains("bad entity reference"));
    // In content, it is skipped unread.
    CHECK(dump(XmlTree::parse("<!DOCTYPE a [<!ENTITY x SYSTEM \"/etc/hostname\">]><a>&x;<b/></a>", kDepth).root()) ==
          "(a@1 (b@1))");
    // A billion laughs: ten levels of ten references each.
    std::string bomb = "<!DOCTYPE a [<!ENTITY e0 \"lol\">";
    for (int i = 1; i < 10; ++i) {
        bomb += "<!ENTITY e" + std::to_string(i) + " \"";
        for (int k = 0; k < 10; ++k) bomb += "&e" + std::to_string(i - 1) + ";";
        bomb += "\">";
    }
    bomb += "]>\n<a v=\"&e9;\"/>";
    CHECK_THAT(failureOf(bomb).message, Contains("entity bomb"));
}

TEST_CASE("XML tree: a read error passes through", "[loader][xml]") {
    auto failing = [](char*, size_t) -> size_t { throw std::runtime_error("disk gone"); };
    CHECK_THROWS_WITH(XmlTree::parse(failing, kDepth), "disk gone");
}

TEST_CASE("with spans, each element knows where its start tag and the whole element lie", "[xml]") {
    // A comment with "--" (rewritten for expat, same length), an entity, a CDATA section,
    // a self-closing element and blanks inside tags.
    const std::string xml =
        "<?xml version=\"1.0\"?>\n<!-- a -- b -->\n<a x = '1' >\n  <b y=\"&amp;\"/>\n"
        "  <c><![CDATA[<d/>]]><d z=\"2\" /></c >\n</a>\n";
    auto spanText = [&](const ray::XmlSpan& s) { return xml.substr(s.begin, s.end - s.begin); };
    auto startTag = [&](const ray::XmlSpan& s) { return xml.substr(s.begin, s.startTagEnd - s.begin); };
    for (size_t piece : {size_t(1), size_t(3), xml.size()}) {
        INFO("pieces of " << piece);
        size_t at = 0;
        XmlTree tree = XmlTree::parse(
            [&](char* buffer, size_t capacity) {
                const size_t n = std::min({capacity, piece, xml.size() - at});
                std::memcpy(buffer, xml.data() + at, n);
                at += n;
                return n;
            },
            kDepth, 0, true);
        REQUIRE(tree.hasSpans());
        REQUIRE(tree.elementCount() == 4);
        CHECK(startTag(tree.element(0).span()) == "<a x = '1' >");
        CHECK(spanText(tree.element(0).span()).size() == xml.size() - xml.find("<a") - 1);
        CHECK(spanText(tree.element(1).span()) == "<b y=\"&amp;\"/>");
        CHECK(tree.element(1).span().startTagEnd == tree.element(1).span().end);  // self-closing
        CHECK(spanText(tree.element(2).span()) == "<c><![CDATA[<d/>]]><d z=\"2\" /></c >");
        CHECK(spanText(tree.element(3).span()) == "<d z=\"2\" />");
        CHECK(tree.element(3).index() == 3);
    }
    CHECK_FALSE(XmlTree::parse(xml, kDepth).hasSpans());
}
