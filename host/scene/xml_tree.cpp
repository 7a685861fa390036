// The XML tree (xml_tree.h), built by libexpat fed a piece at a time (or by the plain reader,
// xml_plain_reader.h, from a plain text in memory).
//
// Security: expat never loads an external entity or external DTD here (no external entity
// handler is set and parameter entities are never parsed), and its protection against entity
// expansion bombs ("billion laughs", on by default since 2.4) stays on.
#include "scene/xml_tree.h"

#include "scene/xml_plain_reader.h"

#include <expat.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

namespace ray {
namespace {

// XML forbids "--" inside a comment, but tinyxml2, the loader's parser before expat, took
// it, and scene files write it (our own scenes quote command-line options such as
// --no-dof in comments). This rewrites such dashes to blanks before expat sees them, with
// a comment ending where tinyxml2 ended it: at the first "-->". Only comment text changes,
// and the loader never reads comments; newlines stay, so line numbers do not move.
//
// The filter skips CDATA sections and processing instructions (either may hold "<!--" as
// text). It stops at a DOCTYPE or any other declaration, whose internal subset may quote
// "<!--" in entity values: after one, comments must be plain XML.
class CommentDashes {
public:
    // Rewrites data[0, size) in place and returns how many bytes are settled: the rest, a
    // few bytes that may begin a marker ("<!-", or "--" that may end a comment), must come
    // again at the front of the next piece. With `last` (no next piece) all are settled.
    size_t apply(char* data, size_t size, bool last) {
        size_t i = 0;
        while (i < size) {
            std::optional<size_t> next;
            switch (state_) {
                case State::Text: next = inText(data, i, size, last); break;
                case State::Comment: next = inComment(data, i, size, last); break;
                case State::CData: next = until(data, i, size, last, "]]>"); break;
                case State::Instruction: next = until(data, i, size, last, "?>"); break;
                case State::Off: return size;
            }
            if (!next) return i;  // hold back from i
            i = *next;
        }
        return size;
    }

private:
    enum class State { Text, Comment, CData, Instruction, Off };
    enum class Match { Yes, No, NeedMore };

    static Match match(const char* at, size_t available, std::string_view pattern) {
        const size_t n = std::min(available, pattern.size());
        if (std::memcmp(at, pattern.data(), n) != 0) return Match::No;
        return n == pattern.size() ? Match::Yes : Match::NeedMore;
    }

    // Where scanning goes on, or nullopt to hold back from `i`.
    std::optional<size_t> inText(const char* data, size_t i, size_t size, bool last) {
        const void* lt = std::memchr(data + i, '<', size - i);
        if (!lt) return size;
        i = size_t(static_cast<const char*>(lt) - data);
        if (i + 1 < size && data[i + 1] != '!' && data[i + 1] != '?') return i + 1;  // a tag, the usual
        const char* at = data + i;
        const size_t available = size - i;
        static constexpr std::pair<std::string_view, State> kMarkers[] = {
            {"<!--", State::Comment}, {"<![CDATA[", State::CData}, {"<!", State::Off}, {"<?", State::Instruction}};
        for (const auto& [marker, state] : kMarkers) {
            const Match m = match(at, available, marker);
            if (m == Match::NeedMore && !last) return std::nullopt;
            if (m == Match::Yes) {
                state_ = state;
                return i + marker.size();
            }
        }
        return i + 1;
    }

    std::optional<size_t> inComment(char* data, size_t i, size_t size, bool last) {
        const void* dash = std::memchr(data + i, '-', size - i);
        if (!dash) return size;
        i = size_t(static_cast<const char*>(dash) - data);
        if (i + 1 < size && data[i + 1] != '-') return i + 1;  // a lone dash
        if (i + 2 >= size) {
            if (last) return size;  // the comment is cut off: expat says so
            return std::nullopt;
        }
        if (data[i + 2] == '>') {  // "-->" ends the comment
            state_ = State::Text;
            return i + 3;
        }
        data[i] = ' ';  // "--" inside: the second dash is looked at next
        return i + 1;
    }

    std::optional<size_t> until(const char* data, size_t i, size_t size, bool last, std::string_view end) {
        const std::string_view rest(data + i, size - i);
        const size_t found = rest.find(end);
        if (found != std::string_view::npos) {
            state_ = State::Text;
            return i + found + end.size();
        }
        if (last) return size;
        // The end marker may straddle this piece and the next: hold back where it could start.
        if (rest.size() < end.size()) return std::nullopt;
        return size - (end.size() - 1);
    }

    State state_ = State::Text;
};

// Element and attribute names, each stored once in the tree's text.
struct NameHash {
    using is_transparent = void;
    size_t operator()(std::string_view name) const { return std::hash<std::string_view>()(name); }
};

bool isBlank(const char* text, size_t size) {
    for (size_t i = 0; i < size; ++i)
        if (!std::isspace(static_cast<unsigned char>(text[i]))) return false;
    return true;
}

// "<name>", for messages. Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on
// "<" + std::string(...).
std::string tagOf(std::string_view name) {
    std::string tag = "<";
    tag.append(name).push_back('>');
    return tag;
}

bool isNameByte(unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == ':' || c >= 0x80;
}

}  // namespace

// Builds an XmlTree from expat's start and end events.
class XmlTreeBuilder {
public:
    // `encoding`: the one to read the text in whatever its declaration says; null: expat's
    // own detection (a byte-order mark, the declaration).
    XmlTreeBuilder(int maxDepth, size_t expectedBytes, bool recordSpans, const char* encoding = nullptr)
        : maxDepth_(maxDepth), recordSpans_(recordSpans), parser_(XML_ParserCreate(encoding)) {
        if (!parser_) throw std::bad_alloc();
        tree_.reserveFor(expectedBytes);
        XML_SetUserData(parser_, this);
        XML_SetElementHandler(parser_, &XmlTreeBuilder::onStart, &XmlTreeBuilder::onEnd);
        // No character data, comment or external entity handler: expat skips text and
        // comments, and skips references to external entities without reading them.
        XML_SetParamEntityParsing(parser_, XML_PARAM_ENTITY_PARSING_NEVER);
    }
    ~XmlTreeBuilder() { XML_ParserFree(parser_); }
    XmlTreeBuilder(const XmlTreeBuilder&) = delete;
    XmlTreeBuilder& operator=(const XmlTreeBuilder&) = delete;

    XmlTree build(const XmlSource& source) {
        std::string carry;  // bytes the comment filter held back, parsed with the next piece
        bool last = false;
        while (!last) {
            const size_t request = carry.size() + kXmlPieceBytes;
            char* buffer = static_cast<char*>(XML_GetBuffer(parser_, int(request)));
            if (!buffer) throw std::bad_alloc();
            std::memcpy(buffer, carry.data(), carry.size());
            const size_t got = source(buffer + carry.size(), kXmlPieceBytes);
            last = got == 0;
            if (!sawNonBlank_) sawNonBlank_ = !isBlank(buffer + carry.size(), got);
            const size_t size = carry.size() + got;
            const size_t settled = comments_.apply(buffer, size, last);
            carry.assign(buffer + settled, size - settled);
            if (XML_ParseBuffer(parser_, int(settled), last) != XML_STATUS_OK) {
                if (rootClosed_) break;  // stopped at the root's end tag: what follows is ignored
                fail();
            }
        }
        return std::move(tree_);
    }

private:
    struct Open {
        uint32_t element;
        uint32_t lastChild;  // 0: none yet
    };

    static void XMLCALL onStart(void* self, const XML_Char* name, const XML_Char** attributes) {
        static_cast<XmlTreeBuilder*>(self)->guarded([&](XmlTreeBuilder& b) { b.start(name, attributes); });
    }
    static void XMLCALL onEnd(void* self, const XML_Char*) {
        static_cast<XmlTreeBuilder*>(self)->guarded([](XmlTreeBuilder& b) { b.end(); });
    }

    // Exceptions must not cross expat's C frames: one thrown in a handler stops the parser
    // and is rethrown once XML_ParseBuffer has returned.
    template <typename Handler>
    void guarded(Handler handler) {
        if (stopped_ || rootClosed_) return;  // expat may call a handler or two after XML_StopParser
        try {
            handler(*this);
        } catch (...) {
            stopped_ = std::current_exception();
            XML_StopParser(parser_, XML_FALSE);
        }
    }

    void start(const char* name, const char** attributes) {
        const int line = currentLine();
        if (open_.size() >= size_t(maxDepth_))
            throw XmlError(XmlError::Kind::TooDeep, line,
                           "elements nest more than " + std::to_string(maxDepth_) + " levels deep");
        if (tree_.elements_.size() >= std::numeric_limits<uint32_t>::max()) tooLarge(line);
        const auto index = uint32_t(tree_.elements_.size());
        // A reference that stays good: nothing below adds elements.
        XmlTree::ElementRecord& element = tree_.elements_.emplace_back();
        element.line = uint32_t(line);
        element.name = intern(name, line);
        element.firstAttribute = uint32_t(tree_.attributes_.size());
        for (const char** a = attributes; a[0]; a += 2)
            tree_.attributes_.push_back({intern(a[0], line), store(a[1], std::strlen(a[1]), line)});
        element.attributeCount = uint32_t(tree_.attributes_.size()) - element.firstAttribute;
        if (recordSpans_) {
            // The start tag is the event being reported: its first byte and its length.
            const auto begin = uint64_t(XML_GetCurrentByteIndex(parser_));
            const auto startTagEnd = begin + uint64_t(XML_GetCurrentByteCount(parser_));
            tree_.spans_.push_back({begin, startTagEnd, startTagEnd});
        }
        if (!open_.empty()) {
            Open& parent = open_.back();
            XmlTree::ElementRecord& before = tree_.elements_[parent.lastChild ? parent.lastChild : parent.element];
            (parent.lastChild ? before.nextSibling : before.firstChild) = index;
            parent.lastChild = index;
        }
        open_.push_back({index, 0});
    }

    void end() {
        if (recordSpans_) {
            // An end tag's event is the tag; a self-closing element's has no bytes of its
            // own (count 0), and ends where its start tag does.
            const int count = XML_GetCurrentByteCount(parser_);
            if (count > 0)
                tree_.spans_[open_.back().element].end = uint64_t(XML_GetCurrentByteIndex(parser_)) + uint64_t(count);
        }
        open_.pop_back();
        if (open_.empty()) {
            rootClosed_ = true;
            XML_StopParser(parser_, XML_FALSE);
        }
    }

    // Names repeat: a small table indexed by a hash of the name remembers where recent ones
    // were stored, so that most lookups end there after one pass over the name's few bytes.
    uint32_t intern(const char* name, int line) {
        uint32_t hash = 0;
        size_t length = 0;
        for (; name[length]; ++length) hash = hash * 31 + static_cast<unsigned char>(name[length]);
        RecentName& recent = recentNames_[hash % kRecentNames];
        if (recent.length == length && recent.offset != kNoName &&
            std::memcmp(&tree_.text_[recent.offset], name, length) == 0)
            return recent.offset;
        const std::string_view key(name, length);
        auto it = names_.find(key);
        if (it == names_.end()) it = names_.emplace(std::string(key), store(name, length, line)).first;
        recent = {it->second, uint32_t(length)};
        return recent.offset;
    }

    uint32_t store(const char* text, size_t length, int line) {
        std::vector<char>& all = tree_.text_;
        if (all.size() + length + 1 > std::numeric_limits<uint32_t>::max()) tooLarge(line);
        const auto offset = uint32_t(all.size());
        all.insert(all.end(), text, text + length + 1);  // with its NUL
        return offset;
    }

    [[noreturn]] static void tooLarge(int line) {
        throw XmlError(XmlError::Kind::TooLarge, line, "the file holds more than 4 GiB of element names and values");
    }

    int currentLine() const {
        const XML_Size line = XML_GetCurrentLineNumber(parser_);
        return line > XML_Size(std::numeric_limits<int>::max()) ? std::numeric_limits<int>::max() : int(line);
    }

    // Turns expat's error into an XmlError; a handler's exception is rethrown as it was.
    [[noreturn]] void fail() {
        if (stopped_) std::rethrow_exception(stopped_);
        const XML_Error code = XML_GetErrorCode(parser_);
        const int line = currentLine();
        if (!sawNonBlank_) throw XmlError(XmlError::Kind::Empty, 0, "the file is empty");
        if (code == XML_ERROR_NO_ELEMENTS && tree_.elements_.empty())
            throw XmlError(XmlError::Kind::NoElement, 0, "the file has no XML element");
        if (code == XML_ERROR_NO_ELEMENTS && !open_.empty())
            throw malformed(innermostLine(), innermostTag() + " is not closed (the file ends first)");
        if (code == XML_ERROR_TAG_MISMATCH && !open_.empty())
            throw malformed(innermostLine(), innermostTag() + " is not closed (the end tag on line " +
                                                 std::to_string(line) + " closes another element)");
        throw malformed(line, describe(code));
    }

    static XmlError malformed(int line, const std::string& message) {
        return XmlError(XmlError::Kind::Malformed, line, message);
    }

    int innermostLine() const { return int(tree_.elements_[open_.back().element].line); }
    std::string innermostTag() const {
        return tagOf(&tree_.text_[tree_.elements_[open_.back().element].name]);
    }

    // The error in words, with the element whose start tag it is in when it is in one.
    std::string describe(XML_Error code) const {
        int offset = 0, size = 0;
        const char* context = XML_GetInputContext(parser_, &offset, &size);
        const bool located = context && offset >= 0 && offset < size;
        if (located && static_cast<unsigned char>(context[offset]) >= 0x80 &&
            (code == XML_ERROR_INVALID_TOKEN || code == XML_ERROR_PARTIAL_CHAR)) {
            char byte[8];
            std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(context[offset]));
            return std::string("byte ") + byte +
                   " is not UTF-8 text (save the file as UTF-8, or name its encoding in a first line "
                   "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>)";
        }
        switch (code) {
            case XML_ERROR_AMPLIFICATION_LIMIT_BREACH:
                return "entity references expand to far more text than the file holds (an entity bomb)";
            case XML_ERROR_MISPLACED_XML_PI: return "the <?xml ...?> declaration is not at the very start of the file";
            case XML_ERROR_UNKNOWN_ENCODING:
            case XML_ERROR_INCORRECT_ENCODING:
                return "the declared encoding is not one ray reads, or not the file's (use UTF-8, UTF-16, "
                       "ISO-8859-1 or US-ASCII)";
            default: break;
        }
        if (located)
            if (auto inTag = describeInStartTag(code, std::string_view(context, size_t(size)), size_t(offset)))
                return *inTag;
        return XML_ErrorString(code);
    }

    // When the error is in a start tag ("<pos x=1/>"), says what is wrong there, naming the
    // element; nullopt otherwise. expat places a bad entity reference at the tag's '<', most
    // other errors where the tag goes wrong; a '>' in a quoted value before that point hides
    // the tag, and the message is then generic.
    static std::optional<std::string> describeInStartTag(XML_Error code, std::string_view context, size_t offset) {
        size_t lt = offset + 1;  // just after the tag's '<'
        if (context[offset] != '<') {
            lt = offset;
            while (lt > 0 && context[lt - 1] != '<' && context[lt - 1] != '>') --lt;
            if (lt == 0 || context[lt - 1] != '<') return std::nullopt;
        }
        size_t nameEnd = lt;
        while (nameEnd < context.size() && isNameByte(static_cast<unsigned char>(context[nameEnd]))) ++nameEnd;
        if (nameEnd == lt) return std::nullopt;  // an end tag, a comment, a declaration
        const std::string tag = tagOf(context.substr(lt, nameEnd - lt));
        switch (code) {
            case XML_ERROR_DUPLICATE_ATTRIBUTE: return tag + " has the same attribute twice";
            case XML_ERROR_UNDEFINED_ENTITY:
            case XML_ERROR_BAD_CHAR_REF:
            case XML_ERROR_BINARY_ENTITY_REF:
            case XML_ERROR_ATTRIBUTE_EXTERNAL_ENTITY_REF:
            case XML_ERROR_RECURSIVE_ENTITY_REF:
                return "an attribute of " + tag + " has a bad entity reference (" + XML_ErrorString(code) +
                       "; write & as &amp;)";
            default: break;
        }
        if (offset < nameEnd) return tag + " is malformed (" + std::string(XML_ErrorString(code)) + ")";
        const std::string_view attributes = context.substr(nameEnd, offset - nameEnd);
        const size_t amp = attributes.rfind('&');
        if (amp != std::string_view::npos && attributes.find(';', amp) == std::string_view::npos)
            return "an attribute of " + tag + " has a bare '&' (write & as &amp;)";
        const char at = context[offset];
        if (offset == nameEnd && at != ' ' && at != '\t' && at != '\n' && at != '\r' && at != '/' && at != '>')
            return tag + " is malformed (" + std::string(XML_ErrorString(code)) + ")";
        return "an attribute of " + tag + " is malformed (values need quotes: write name=\"value\")";
    }

    int maxDepth_;
    bool recordSpans_;
    XML_Parser parser_;
    XmlTree tree_;
    std::vector<Open> open_;
    std::unordered_map<std::string, uint32_t, NameHash, std::equal_to<>> names_;
    static constexpr size_t kRecentNames = 64;
    static constexpr uint32_t kNoName = std::numeric_limits<uint32_t>::max();
    struct RecentName {
        uint32_t offset = kNoName;  // in the text
        uint32_t length = 0;
    };
    std::array<RecentName, kRecentNames> recentNames_{};
    CommentDashes comments_;
    bool sawNonBlank_ = false;
    bool rootClosed_ = false;
    std::exception_ptr stopped_;
};

XmlTree XmlTree::parse(const XmlSource& source, int maxDepth, size_t expectedBytes, bool recordSpans) {
    return XmlTreeBuilder(maxDepth, expectedBytes, recordSpans).build(source);
}

namespace {

XmlSource readingFrom(std::string_view text) {
    return [text, at = size_t(0)](char* buffer, size_t capacity) mutable {
        const size_t n = std::min(capacity, text.size() - at);
        std::memcpy(buffer, text.data() + at, n);
        at += n;
        return n;
    };
}

}  // namespace

XmlTree XmlTree::parse(std::string_view text, int maxDepth, bool recordSpans) {
    if (std::optional<XmlTree> plain = readPlainXml(text, maxDepth, recordSpans)) return std::move(*plain);
    return parse(readingFrom(text), maxDepth, text.size(), recordSpans);
}

XmlTree XmlTree::parseUtf8(std::string_view text, int maxDepth, bool recordSpans) {
    return XmlTreeBuilder(maxDepth, text.size(), recordSpans, "UTF-8").build(readingFrom(text));
}

// A scene element takes 35 to 40 bytes of text, an attribute 15 to 18, and names and
// values a third of the text. Generous, since room reserved and never used costs address
// space, not memory.
void XmlTree::reserveFor(size_t bytes) {
    const size_t cap = std::numeric_limits<uint32_t>::max();
    elements_.reserve(std::min(bytes / 24, cap));
    attributes_.reserve(std::min(bytes / 10, cap));
    text_.reserve(std::min(bytes / 2, cap));
}

size_t XmlTree::bytes() const {
    return elements_.capacity() * sizeof(ElementRecord) + attributes_.capacity() * sizeof(AttributeRecord) +
           text_.capacity() + spans_.capacity() * sizeof(XmlSpan);
}

void XmlTree::clear() { *this = XmlTree(); }

}  // namespace ray
