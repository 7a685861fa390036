// A scene file's text as it was read, and where each of its elements lies in it: what a
// save keeps of the file (scene_document.h, documentToText).
//
// A save is the file's text with splices applied: each splice replaces a range of the
// original bytes (empty for an insertion) with new text, so that everything no edit
// touched (comments, element order, attribute spelling and quotes, numbers as written,
// blanks) comes out byte for byte. Elements are addressed by SourceId, their index in the
// XML tree (document order; the root is 0), which document nodes keep (kNoSource for
// what was made in code).
//
// The places come from expat's byte offsets (xml_tree.h, XmlSpan): the start tag's first
// byte and length, the end tag's end. Attributes are found by scanning the start tag,
// which expat has already checked. The text is UTF-8, as the splices are: a file in
// another encoding (ISO-8859-1, US-ASCII, UTF-16) is held as its text in UTF-8, parsed
// again from that, and a save's text is turned back into the file's encoding
// (text_encoding.h; fileBytes), so that it stays in it and keeps what no edit touched.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/text_encoding.h"
#include "scene/xml_tree.h"

namespace ray {

using SourceId = uint32_t;
constexpr SourceId kNoSource = std::numeric_limits<SourceId>::max();

// Replaces [begin, end) of the original text with `text`; begin == end inserts.
struct Splice {
    size_t begin = 0, end = 0;
    std::string text;
};

// `original` with `splices` applied. Splices are taken in order of `begin`, insertions at
// one place in the order given and before a replacement starting there; they must not
// overlap. Throws std::logic_error when they do.
std::string applySplices(std::string_view original, std::vector<Splice> splices);

class SourceText {
public:
    // `tree` must have been parsed from `text`, UTF-8, with spans (XmlTree::hasSpans). A
    // file in another `encoding` gives its own bytes too (`fileBytes`): a save that
    // changes nothing writes them as they were.
    SourceText(std::string text, XmlTree tree, TextEncoding encoding = TextEncoding::Utf8, std::string fileBytes = {});

    // The text, in UTF-8 (for a file in UTF-8, its bytes).
    const std::string& bytes() const { return bytes_; }
    // The file's encoding, and `text` (this text with splices applied) as the file's bytes:
    // in its encoding, its own bytes when `text` is its text.
    TextEncoding encoding() const { return encoding_; }
    std::string fileBytes(const std::string& text) const;
    const XmlTree& tree() const { return tree_; }
    size_t elementCount() const { return tree_.elementCount(); }
    XmlElement element(SourceId id) const { return tree_.element(id); }
    const XmlSpan& span(SourceId id) const { return element(id).span(); }
    SourceId parent(SourceId id) const { return parents_[id]; }  // kNoSource for the root
    bool selfClosing(SourceId id) const { return span(id).startTagEnd == span(id).end; }

    // The line break the file uses ("\r\n" or "\n"), and one step of its indentation (the
    // first found between an element and its parent's; two blanks when none is).
    const std::string& newline() const { return newline_; }
    const std::string& indentUnit() const { return indentUnit_; }

    // The blanks before the element on its line, when nothing else is (nullopt otherwise).
    std::optional<std::string_view> indentation(SourceId id) const;
    // The range an element's removal takes away: its own lines when it has them to itself
    // (from its line's start to past its last line's break), else the element alone.
    std::pair<size_t, size_t> removalRange(SourceId id) const;

    // An attribute of a start tag as written: the value's bytes lie in [valueBegin,
    // valueEnd), between quotes `quote`.
    struct Attribute {
        std::string_view name;
        size_t valueBegin = 0, valueEnd = 0;
        char quote = '"';
    };
    // The attributes of the element's start tag, in the order written.
    std::vector<Attribute> attributes(SourceId id) const;
    // Where new attributes go: just after the last attribute (or the name) of the start tag.
    size_t attributeInsertion(SourceId id) const;

private:
    std::string bytes_;
    XmlTree tree_;
    std::vector<SourceId> parents_;
    TextEncoding encoding_ = TextEncoding::Utf8;
    std::string fileBytes_;  // a file not in UTF-8: its bytes as read
    std::string newline_ = "\n", indentUnit_ = "  ";
};

}  // namespace ray
