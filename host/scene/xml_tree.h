// An XML document as a compact, read-only tree of elements and their attributes, built by
// libexpat's streaming parser from text read a piece at a time, or, from a text in memory
// that is plain XML (scene/xml_plain_reader.h), in one pass without expat.
//
// The scene format (SPEC §1) lives entirely in element names and attributes, so that is all
// the tree keeps: character data, comments and processing instructions are skipped. A large
// flat scene has millions of elements; the tree holds them in three arrays (see XmlTree),
// with no allocation per element; expat's reading of a stream never holds its text in one piece.
//
// On request the tree also records where each element lies in the text (XmlSpan, from
// expat's byte offsets): what lets a saved scene keep the text of what was not edited
// (scene/source_text.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ray {

// Why a text is not an XML tree: what() says what is wrong, in words, without the file's
// name; line is where (1-based), 0 when no line applies.
class XmlError : public std::runtime_error {
public:
    enum class Kind {
        Empty,      // nothing but blanks
        NoElement,  // no element at all (only comments, say)
        Malformed,  // not well-formed XML
        TooDeep,    // elements nested deeper than the limit given to parse
        TooLarge,   // over 4 GiB of names and values (the tree's offsets are 32-bit)
    };
    XmlError(Kind kind, int line, const std::string& message) : std::runtime_error(message), kind(kind), line(line) {}
    Kind kind;
    int line;
};

// Fills `buffer` with up to `capacity` bytes of the document and returns how many; 0 means
// the document has ended. It may throw (a read error): the exception passes through parse.
using XmlSource = std::function<size_t(char* buffer, size_t capacity)>;

// The size of each piece read from an XmlSource and parsed: large enough that the calls
// cost nothing, small enough that a scene of tens of megabytes is never held whole.
constexpr size_t kXmlPieceBytes = 1 << 20;

class XmlTree;

// Where an element lies in the bytes parsed: [begin, end) is the whole element, start tag
// to end tag; [begin, startTagEnd) its start tag. A self-closing element (<a/>) has
// startTagEnd == end.
struct XmlSpan {
    uint64_t begin = 0, startTagEnd = 0, end = 0;
};

// An element of an XmlTree: a handle (the tree and an index), cheap to copy, valid while
// the tree lives. A default-constructed one names no element and converts to false.
class XmlElement {
public:
    XmlElement() = default;
    explicit operator bool() const { return tree_ != nullptr; }

    const char* name() const;
    int line() const;  // of its start tag
    size_t attributeCount() const;
    // Attributes in the order written; i < attributeCount().
    const char* attributeName(size_t i) const;
    const char* attributeValue(size_t i) const;
    // The first child element and the next sibling element; false when there is none.
    XmlElement firstChild() const;
    XmlElement nextSibling() const;
    // Its place in document order (the root is 0): XmlTree::element(index()) is this one.
    uint32_t index() const { return index_; }
    // Where it lies in the text; only for a tree parsed with spans (XmlTree::hasSpans).
    const XmlSpan& span() const;

private:
    friend class XmlTree;
    XmlElement(const XmlTree* tree, uint32_t index) : tree_(tree), index_(index) {}
    const XmlTree* tree_ = nullptr;
    uint32_t index_ = 0;
};

class XmlTree {
public:
    // Parses a document read from `source`. Elements nested deeper than maxDepth are refused
    // (XmlError::Kind::TooDeep): the tree itself needs no recursion, but whoever walks it does.
    // `expectedBytes`, the document's size when known (0: unknown), sizes the arrays up
    // front, so that they are not copied as they grow. Throws XmlError, or what `source` throws.
    // With `recordSpans`, each element's place in the bytes read is kept too (XmlSpan).
    static XmlTree parse(const XmlSource& source, int maxDepth, size_t expectedBytes = 0, bool recordSpans = false);
    // The same from a text in memory: read in one pass when it is plain XML (the usual
    // scene file), else by expat; the same tree, and the same errors, either way.
    static XmlTree parse(std::string_view text, int maxDepth, bool recordSpans = false);
    // `text` read as UTF-8 whatever encoding its XML declaration names: a file's text turned
    // into UTF-8 (scene/text_encoding.h), its declaration kept as the file has it.
    static XmlTree parseUtf8(std::string_view text, int maxDepth, bool recordSpans);

    XmlTree() = default;
    XmlTree(XmlTree&&) = default;
    XmlTree& operator=(XmlTree&&) = default;
    XmlTree(const XmlTree&) = delete;  // handles point at the tree: copies would confuse them
    XmlTree& operator=(const XmlTree&) = delete;

    // The root element; false for an empty tree (a default-constructed or cleared one).
    XmlElement root() const { return elements_.empty() ? XmlElement() : XmlElement(this, 0); }
    size_t elementCount() const { return elements_.size(); }
    // The element at `index` (< elementCount()), in document order.
    XmlElement element(uint32_t index) const { return XmlElement(this, index); }
    bool hasSpans() const { return !spans_.empty() || elements_.empty(); }
    size_t attributeCount() const { return attributes_.size(); }
    // The memory the tree holds, for measurements.
    size_t bytes() const;
    // Frees everything; handles into the tree must not be used after this.
    void clear();

private:
    friend class XmlElement;
    friend class XmlTreeBuilder;
    friend class PlainXmlReader;  // scene/xml_plain_reader.h

    // Reserves room for what a document of `bytes` usually holds, so that the arrays are
    // not copied as they grow.
    void reserveFor(size_t bytes);

    // The layout. Elements are records in document order, so elements_[0] is the root and
    // every parent comes before its children; index 0 therefore never names a child or a
    // sibling, and 0 in firstChild or nextSibling means "none". An element's attributes are
    // the attributeCount records of attributes_ from firstAttribute, in the order written.
    // Names and values are NUL-terminated strings in text_, addressed by their offset;
    // each distinct element or attribute name is stored once (a scene repeats a few dozen
    // names millions of times). 24 bytes an element, 8 an attribute, plus the values' text.
    struct ElementRecord {
        uint32_t name = 0;  // offset in text_
        uint32_t firstAttribute = 0;
        uint32_t attributeCount = 0;
        uint32_t firstChild = 0;
        uint32_t nextSibling = 0;
        uint32_t line = 0;
    };
    struct AttributeRecord {
        uint32_t name = 0;   // offset in text_
        uint32_t value = 0;  // offset in text_
    };

    std::vector<ElementRecord> elements_;
    std::vector<AttributeRecord> attributes_;
    std::vector<char> text_;
    std::vector<XmlSpan> spans_;  // one per element, when parsed with spans; empty otherwise
};

inline const char* XmlElement::name() const { return &tree_->text_[tree_->elements_[index_].name]; }
inline int XmlElement::line() const { return int(tree_->elements_[index_].line); }
inline size_t XmlElement::attributeCount() const { return tree_->elements_[index_].attributeCount; }
inline const char* XmlElement::attributeName(size_t i) const {
    return &tree_->text_[tree_->attributes_[tree_->elements_[index_].firstAttribute + i].name];
}
inline const char* XmlElement::attributeValue(size_t i) const {
    return &tree_->text_[tree_->attributes_[tree_->elements_[index_].firstAttribute + i].value];
}
inline const XmlSpan& XmlElement::span() const { return tree_->spans_[index_]; }
inline XmlElement XmlElement::firstChild() const {
    const uint32_t child = tree_->elements_[index_].firstChild;
    return child ? XmlElement(tree_, child) : XmlElement();
}
inline XmlElement XmlElement::nextSibling() const {
    const uint32_t sibling = tree_->elements_[index_].nextSibling;
    return sibling ? XmlElement(tree_, sibling) : XmlElement();
}

}  // namespace ray
