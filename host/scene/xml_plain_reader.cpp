// The one-pass reader of plain XML (xml_plain_reader.h).
//
// It builds the tree as XmlTreeBuilder (xml_tree.cpp) does from expat's events: the same
// records in document order, names stored once, values with their blanks normalized as
// XML says (a tab or a line break in a value reads as a blank), the line of each start
// tag's '<', and spans as byte offsets into `text`. Where it meets anything it does not
// take, it stops with NotPlain and expat reads the text instead.
#include "scene/xml_plain_reader.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace ray {
namespace {

// Thrown where the text leaves the plain subset (or is wrong): expat reads it then.
struct NotPlain {};
// Thrown where a tag runs past the window's end (a source's piece): the tag is read again
// once the next piece is in. Elsewhere it means what NotPlain means.
struct PastTheWindow : NotPlain {};

// What each byte may be, as bits.
enum ByteClass : uint8_t {
    kBlank = 1,         // XML's white space: space, tab, line feed, carriage return
    kNameStart = 2,     // first byte of a name
    kNameByte = 4,      // any byte of a name
    kTextByte = 8,      // between tags (not '<', '&' or ']', so never "]]>")
    kValueByte = 16,    // in an attribute's value (not '<', '&' or a carriage return)
    kCommentByte = 32,  // in a comment
};

constexpr std::array<uint8_t, 256> kByteClasses = [] {
    std::array<uint8_t, 256> classes{};
    for (int c = 0x20; c < 0x7F; ++c) classes[size_t(c)] = kTextByte | kValueByte | kCommentByte;
    for (int c : {'<', '&', ']'}) classes[size_t(c)] &= uint8_t(~kTextByte);
    for (int c : {'<', '&'}) classes[size_t(c)] &= uint8_t(~kValueByte);
    for (int c : {' ', '\t', '\n', '\r'}) classes[size_t(c)] |= kBlank | kTextByte | kCommentByte;
    for (int c : {'\t', '\n'}) classes[size_t(c)] |= kValueByte;
    for (int c = 'a'; c <= 'z'; ++c) classes[size_t(c)] |= kNameStart | kNameByte;
    for (int c = 'A'; c <= 'Z'; ++c) classes[size_t(c)] |= kNameStart | kNameByte;
    for (int c = '0'; c <= '9'; ++c) classes[size_t(c)] |= kNameByte;
    classes[size_t('_')] |= kNameStart | kNameByte;
    for (int c : {'.', '-'}) classes[size_t(c)] |= kNameByte;
    return classes;
}();

bool is(char c, ByteClass byteClass) { return kByteClasses[static_cast<unsigned char>(c)] & byteClass; }

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return (x | 0x20) == (y | 0x20);  // letters and '-', '8' alike
           });
}

}  // namespace

class PlainXmlReader {
public:
    // Reads `text`, whole in memory.
    PlainXmlReader(std::string_view text, int maxDepth, bool recordSpans)
        : begin_(text.data()), end_(text.data() + text.size()), at_(begin_), counted_(begin_), ended_(true),
          maxDepth_(maxDepth), recordSpans_(recordSpans) {
        tree_.reserveFor(text.size());
    }
    // Reads what `source` gives, a piece at a time.
    PlainXmlReader(const XmlSource& source, size_t expectedBytes, int maxDepth, bool recordSpans)
        : source_(&source), maxDepth_(maxDepth), recordSpans_(recordSpans) {
        tree_.reserveFor(expectedBytes);
    }

    XmlTree read() {
        constexpr std::string_view kUtf8Mark = "\xEF\xBB\xBF";
        ensureBytes(kUtf8Mark.size());
        if (startsWith(kUtf8Mark)) at_ += kUtf8Mark.size();
        ensureBytes(6);
        if (startsWith("<?xml") && end_ - at_ > 5 && is(at_[5], kBlank)) {
            ensureThrough("?>", 5);
            readDeclaration();
        }
        skipBlanksAndComments();
        if (at_ == end_ || *at_ != '<') throw NotPlain();
        while (!readMarkup()) skipText();
        return std::move(tree_);
    }

private:
    struct Open {
        uint32_t element;
        uint32_t lastChild;  // 0: none yet
    };

    // Where `place` in the window lies in the whole text.
    uint64_t offsetOf(const char* place) const { return base_ + uint64_t(place - begin_); }

    std::string_view nameOf(uint32_t element) const { return &tree_.text_[tree_.elements_[element].name]; }

    // The window: a text in memory is one; a source's pieces come into buffer_, and what
    // the reader has not passed yet (at_ on) moves to its front as the next piece comes.
    // A construct (a tag, a comment) is made whole in the window before it is read, so
    // that no pointer into the window outlives a move.

    // Reads more after what is left of the window: a piece, or as much as is left when that
    // is more (a tag longer than a piece is read again from its start each time the window
    // grows: doubling it keeps that linear). False once the source has ended (the window
    // unchanged then).
    bool more() {
        if (ended_) return false;
        lineAt(at_);  // lines of what leaves the window are counted before it goes
        const size_t kept = size_t(end_ - at_);
        const size_t wanted = std::max(kXmlPieceBytes, kept);
        if (buffer_.size() < kept + wanted) {
            std::vector<char> larger(kept + wanted);
            if (kept) std::memcpy(larger.data(), at_, kept);
            buffer_.swap(larger);
        } else if (kept) {
            std::memmove(buffer_.data(), at_, kept);
        }
        base_ += uint64_t(at_ - begin_);
        size_t got = 0;
        while (got < wanted && !ended_) {
            const size_t n = (*source_)(buffer_.data() + kept + got, wanted - got);
            ended_ = n == 0;
            got += n;
        }
        begin_ = at_ = counted_ = buffer_.data();
        end_ = begin_ + kept + got;
        return got > 0;
    }

    void ensureBytes(size_t count) {
        while (size_t(end_ - at_) < count && more()) {
        }
    }

    // Makes the window hold `marker` after at_ + `from`, if the text does.
    void ensureThrough(std::string_view marker, size_t from) {
        for (;;) {
            const std::string_view rest(at_, size_t(end_ - at_));
            if (rest.size() >= from && rest.find(marker, from) != std::string_view::npos) return;
            if (rest.size() > marker.size()) from = std::max(from, rest.size() - marker.size());
            if (!more()) return;
        }
    }

    bool startsWith(std::string_view prefix) const {
        return size_t(end_ - at_) >= prefix.size() && std::memcmp(at_, prefix.data(), prefix.size()) == 0;
    }

    bool skipBlanks() {
        const char* from = at_;
        while (at_ < end_ && is(*at_, kBlank)) ++at_;
        return at_ != from;
    }

    // At the window's end, inside a tag.
    [[noreturn]] void pastTheEnd() const {
        if (ended_) throw NotPlain();
        throw PastTheWindow();
    }

    void expect(char c) {
        if (at_ == end_) pastTheEnd();
        if (*at_ != c) throw NotPlain();
        ++at_;
    }

    std::string_view readName() {
        const char* name = at_;
        if (at_ == end_) pastTheEnd();
        if (!is(*at_, kNameStart)) throw NotPlain();
        while (at_ < end_ && is(*at_, kNameByte)) ++at_;
        if (at_ == end_) pastTheEnd();  // the name may go on
        return {name, size_t(at_ - name)};
    }

    // At '"' or '\'': the quoted text after it, up to its closing quote, passed. Its bytes
    // must all be `allowed`; whether a tab or a line break is among them goes to `breaks`.
    std::string_view readQuoted(ByteClass allowed, bool& breaks) {
        if (at_ == end_) pastTheEnd();
        if (*at_ != '"' && *at_ != '\'') throw NotPlain();
        const char quote = *at_++;
        const char* value = at_;
        breaks = false;
        for (; at_ < end_ && *at_ != quote; ++at_) {
            if (!is(*at_, allowed)) throw NotPlain();
            breaks |= *at_ == '\t' || *at_ == '\n';
        }
        if (at_ == end_) pastTheEnd();
        return {value, size_t(at_++ - value)};
    }

    // <?xml version="1.0" encoding="UTF-8" standalone="yes"?>, encoding and standalone
    // optional: what expat reads as UTF-8 text. Anything else there is expat's to judge.
    void readDeclaration() {
        at_ += 5;
        auto pseudoAttribute = [&](std::string_view name) -> std::optional<std::string_view> {
            const char* from = at_;
            if (!skipBlanks() || !startsWith(name)) {
                at_ = from;
                return std::nullopt;
            }
            at_ += name.size();
            skipBlanks();
            expect('=');
            skipBlanks();
            bool breaks = false;
            return readQuoted(kNameByte, breaks);
        };
        if (pseudoAttribute("version") != "1.0") throw NotPlain();
        if (auto encoding = pseudoAttribute("encoding"); encoding && !equalsIgnoringCase(*encoding, "utf-8"))
            throw NotPlain();
        if (auto standalone = pseudoAttribute("standalone"); standalone && *standalone != "yes" && *standalone != "no")
            throw NotPlain();
        skipBlanks();
        if (!startsWith("?>")) throw NotPlain();
        at_ += 2;
    }

    // At "<!--": past the first "-->" after it. A "--" inside is taken, as the loader
    // takes it (xml_tree.cpp, CommentDashes).
    void skipComment() {
        ensureThrough("-->", 4);
        const std::string_view rest(at_ + 4, size_t(end_ - at_) - 4);
        const size_t close = rest.find("-->");
        if (close == std::string_view::npos) throw NotPlain();
        for (char c : rest.substr(0, close))
            if (!is(c, kCommentByte)) throw NotPlain();
        at_ = rest.data() + close + 3;
    }

    void skipBlanksAndComments() {
        for (;;) {
            skipBlanks();
            if (at_ == end_ && more()) continue;
            ensureBytes(4);
            if (!startsWith("<!--")) return;
            skipComment();
        }
    }

    // Text between tags, up to the next '<'.
    void skipText() {
        for (;;) {
            for (; at_ < end_ && *at_ != '<'; ++at_)
                if (!is(*at_, kTextByte)) throw NotPlain();
            if (at_ < end_) return;
            if (!more()) throw NotPlain();  // an element is not closed
        }
    }

    // At '<': a start tag, an end tag or a comment, read. True once the root is closed.
    bool readMarkup() {
        ensureBytes(4);
        if (end_ - at_ < 2) throw NotPlain();
        if (at_[1] == '!') {
            if (!startsWith("<!--")) throw NotPlain();  // CDATA, or a declaration
            skipComment();
            return false;
        }
        // A tag cut off by the window's end is read again, whole, from its '<'.
        const char* tag = at_;
        const size_t elements = tree_.elements_.size(), attributes = tree_.attributes_.size();
        for (;;) {
            try {
                return at_[1] == '/' ? readEndTag() : readStartTag();
            } catch (const PastTheWindow&) {
                tree_.elements_.resize(elements);  // a start tag added its element and attributes
                tree_.attributes_.resize(attributes);
                at_ = tag;
                if (!more()) throw NotPlain();
                tag = at_;
            }
        }
    }

    bool readStartTag() {
        const char* tag = at_++;
        if (open_.size() >= size_t(maxDepth_) || tree_.elements_.size() >= std::numeric_limits<uint32_t>::max())
            throw NotPlain();
        const auto index = uint32_t(tree_.elements_.size());
        XmlTree::ElementRecord& element = tree_.elements_.emplace_back();
        element.line = lineAt(tag);
        element.name = intern(readName());
        element.firstAttribute = uint32_t(tree_.attributes_.size());
        bool selfClosing = false;
        for (;;) {
            const bool blank = skipBlanks();
            if (at_ == end_) pastTheEnd();
            if (*at_ == '>') {
                ++at_;
                break;
            }
            if (*at_ == '/') {
                ++at_;
                expect('>');
                selfClosing = true;
                break;
            }
            if (!blank) throw NotPlain();  // attributes are set apart by blanks
            readAttribute();
        }
        element.attributeCount = uint32_t(tree_.attributes_.size()) - element.firstAttribute;
        refuseRepeatedAttributes(element);
        if (recordSpans_) {
            const uint64_t startTagEnd = offsetOf(at_);
            tree_.spans_.push_back({offsetOf(tag), startTagEnd, startTagEnd});
        }
        linkToParent(index);
        if (!selfClosing) open_.push_back({index, 0});
        return open_.empty();
    }

    void readAttribute() {
        const std::string_view name = readName();
        skipBlanks();
        expect('=');
        skipBlanks();
        bool breaks = false;
        const std::string_view value = readQuoted(kValueByte, breaks);
        tree_.attributes_.push_back({intern(name), store(value, breaks)});
    }

    // Names are interned, so that one written twice has one offset. A scene's element has
    // a few attributes, compared pairwise; a long list is sorted instead.
    void refuseRepeatedAttributes(const XmlTree::ElementRecord& element) {
        const XmlTree::AttributeRecord* first = tree_.attributes_.data() + element.firstAttribute;
        if (element.attributeCount <= 16) {
            for (uint32_t i = 1; i < element.attributeCount; ++i)
                for (uint32_t k = 0; k < i; ++k)
                    if (first[i].name == first[k].name) throw NotPlain();
            return;
        }
        sortedNames_.clear();
        for (uint32_t i = 0; i < element.attributeCount; ++i) sortedNames_.push_back(first[i].name);
        std::sort(sortedNames_.begin(), sortedNames_.end());
        if (std::adjacent_find(sortedNames_.begin(), sortedNames_.end()) != sortedNames_.end()) throw NotPlain();
    }

    void linkToParent(uint32_t index) {
        if (open_.empty()) return;
        Open& parent = open_.back();
        XmlTree::ElementRecord& before = tree_.elements_[parent.lastChild ? parent.lastChild : parent.element];
        (parent.lastChild ? before.nextSibling : before.firstChild) = index;
        parent.lastChild = index;
    }

    bool readEndTag() {
        at_ += 2;
        if (open_.empty() || readName() != nameOf(open_.back().element)) throw NotPlain();
        skipBlanks();
        expect('>');
        if (recordSpans_) tree_.spans_[open_.back().element].end = offsetOf(at_);
        open_.pop_back();
        return open_.empty();
    }

    // The line of `place`, counted as expat counts: a line feed, a carriage return and the
    // two together each end a line. Places are asked for in document order; a "\r\n"
    // may fall across two counts (the window's end between them).
    uint32_t lineAt(const char* place) {
        if (place <= counted_) return line_;
        const char* from = counted_;
        if (afterCarriageReturn_ && *from == '\n') ++from;  // counted with its '\r'
        const std::string_view range(from, size_t(place - from));
        if (range.find('\r') == std::string_view::npos) {
            line_ += uint32_t(std::count(range.begin(), range.end(), '\n'));
        } else {
            for (size_t i = 0; i < range.size(); ++i) {
                if (range[i] == '\n' || range[i] == '\r') ++line_;
                if (range[i] == '\r' && i + 1 < range.size() && range[i + 1] == '\n') ++i;
            }
        }
        afterCarriageReturn_ = place[-1] == '\r';
        counted_ = place;
        return line_;
    }

    uint32_t intern(std::string_view name) {
        uint32_t hash = 0;
        for (char c : name) hash = hash * 31 + static_cast<unsigned char>(c);
        RecentName& recent = recentNames_[hash % kRecentNames];
        if (recent.offset != kNoName && recent.length == name.size() &&
            std::memcmp(&tree_.text_[recent.offset], name.data(), name.size()) == 0)
            return recent.offset;
        auto it = names_.find(name);
        if (it == names_.end()) it = names_.emplace(std::string(name), store(name, false)).first;
        recent = {it->second, uint32_t(name.size())};
        return recent.offset;
    }

    // `text` appended to the tree's text with its NUL; with `breaks`, its tabs and line
    // feeds as blanks (attribute-value normalization).
    uint32_t store(std::string_view text, bool breaks) {
        std::vector<char>& all = tree_.text_;
        if (all.size() + text.size() + 1 > std::numeric_limits<uint32_t>::max()) throw NotPlain();
        const auto offset = uint32_t(all.size());
        all.insert(all.end(), text.begin(), text.end());
        if (breaks) std::replace_if(all.begin() + offset, all.end(), [](char c) { return c == '\t' || c == '\n'; }, ' ');
        all.push_back('\0');
        return offset;
    }

    const XmlSource* source_ = nullptr;  // null: the text is in memory, whole
    std::vector<char> buffer_;           // a source's window
    const char* begin_ = nullptr;        // the window
    const char* end_ = nullptr;
    const char* at_ = nullptr;           // the next byte to read
    const char* counted_ = nullptr;      // lines are counted up to here
    uint64_t base_ = 0;                  // the offset of begin_ in the whole text
    bool ended_ = false;                 // no bytes after end_
    uint32_t line_ = 1;
    bool afterCarriageReturn_ = false;   // counted_ follows a '\r'
    int maxDepth_;
    bool recordSpans_;
    XmlTree tree_;
    std::vector<Open> open_;
    // Names read, and where the tree's text holds them (a view into the window would not
    // outlive it). Looked up only when the small table of recent names misses.
    struct NameHash {
        using is_transparent = void;
        size_t operator()(std::string_view name) const { return std::hash<std::string_view>()(name); }
    };
    std::unordered_map<std::string, uint32_t, NameHash, std::equal_to<>> names_;
    std::vector<uint32_t> sortedNames_;  // a long attribute list's names (refuseRepeatedAttributes)
    static constexpr size_t kRecentNames = 64;
    static constexpr uint32_t kNoName = std::numeric_limits<uint32_t>::max();
    struct RecentName {
        uint32_t offset = kNoName;
        uint32_t length = 0;
    };
    std::array<RecentName, kRecentNames> recentNames_{};
};

std::optional<XmlTree> readPlainXml(std::string_view text, int maxDepth, bool recordSpans) {
    try {
        return PlainXmlReader(text, maxDepth, recordSpans).read();
    } catch (const NotPlain&) {
        return std::nullopt;
    }
}

std::optional<XmlTree> readPlainXml(const XmlSource& source, size_t expectedBytes, int maxDepth, bool recordSpans) {
    try {
        return PlainXmlReader(source, expectedBytes, maxDepth, recordSpans).read();
    } catch (const NotPlain&) {
        return std::nullopt;
    }
}

}  // namespace ray
