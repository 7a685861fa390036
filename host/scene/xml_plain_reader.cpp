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
    PlainXmlReader(std::string_view text, int maxDepth, bool recordSpans)
        : begin_(text.data()),
          end_(text.data() + text.size()),
          at_(begin_),
          counted_(begin_),
          maxDepth_(maxDepth),
          recordSpans_(recordSpans),
          carriageReturns_(std::memchr(text.data(), '\r', text.size()) != nullptr) {
        tree_.reserveFor(text.size());
    }

    XmlTree read() {
        constexpr std::string_view kUtf8Mark = "\xEF\xBB\xBF";
        if (startsWith(kUtf8Mark)) at_ += kUtf8Mark.size();
        if (startsWith("<?xml") && end_ - at_ > 5 && is(at_[5], kBlank)) readDeclaration();
        skipBlanksAndComments();
        if (at_ == end_ || *at_ != '<') throw NotPlain();
        while (!readMarkup()) skipText();
        return std::move(tree_);
    }

private:
    struct Open {
        uint32_t element;
        uint32_t lastChild;  // 0: none yet
        std::string_view name;
    };

    bool startsWith(std::string_view prefix) const {
        return size_t(end_ - at_) >= prefix.size() && std::memcmp(at_, prefix.data(), prefix.size()) == 0;
    }

    bool skipBlanks() {
        const char* from = at_;
        while (at_ < end_ && is(*at_, kBlank)) ++at_;
        return at_ != from;
    }

    void expect(char c) {
        if (at_ == end_ || *at_ != c) throw NotPlain();
        ++at_;
    }

    std::string_view readName() {
        const char* name = at_;
        if (at_ == end_ || !is(*at_, kNameStart)) throw NotPlain();
        while (at_ < end_ && is(*at_, kNameByte)) ++at_;
        return {name, size_t(at_ - name)};
    }

    // At '"' or '\'': the quoted text after it, up to its closing quote, passed. Its bytes
    // must all be `allowed`; whether a tab or a line break is among them goes to `breaks`.
    std::string_view readQuoted(ByteClass allowed, bool& breaks) {
        if (at_ == end_ || (*at_ != '"' && *at_ != '\'')) throw NotPlain();
        const char quote = *at_++;
        const char* value = at_;
        breaks = false;
        for (; at_ < end_ && *at_ != quote; ++at_) {
            if (!is(*at_, allowed)) throw NotPlain();
            breaks |= *at_ == '\t' || *at_ == '\n';
        }
        if (at_ == end_) throw NotPlain();
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
        const std::string_view rest(at_ + 4, size_t(end_ - at_) - 4);
        const size_t close = rest.find("-->");
        if (close == std::string_view::npos) throw NotPlain();
        for (char c : rest.substr(0, close))
            if (!is(c, kCommentByte)) throw NotPlain();
        at_ = rest.data() + close + 3;
    }

    void skipBlanksAndComments() {
        for (skipBlanks(); startsWith("<!--"); skipBlanks()) skipComment();
    }

    // Text between tags, up to the next '<'.
    void skipText() {
        for (; at_ < end_ && *at_ != '<'; ++at_)
            if (!is(*at_, kTextByte)) throw NotPlain();
        if (at_ == end_) throw NotPlain();  // an element is not closed
    }

    // At '<': a start tag, an end tag or a comment, read. True once the root is closed.
    bool readMarkup() {
        if (end_ - at_ < 2) throw NotPlain();
        if (at_[1] == '/') return readEndTag();
        if (at_[1] == '!') {
            if (!startsWith("<!--")) throw NotPlain();  // CDATA, or a declaration
            skipComment();
            return false;
        }
        return readStartTag();
    }

    bool readStartTag() {
        const char* tag = at_++;
        if (open_.size() >= size_t(maxDepth_) || tree_.elements_.size() >= std::numeric_limits<uint32_t>::max())
            throw NotPlain();
        const auto index = uint32_t(tree_.elements_.size());
        XmlTree::ElementRecord& element = tree_.elements_.emplace_back();
        element.line = lineAt(tag);
        const std::string_view name = readName();
        element.name = intern(name);
        element.firstAttribute = uint32_t(tree_.attributes_.size());
        bool selfClosing = false;
        for (;;) {
            const bool blank = skipBlanks();
            if (at_ == end_) throw NotPlain();
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
            const auto startTagEnd = uint64_t(at_ - begin_);
            tree_.spans_.push_back({uint64_t(tag - begin_), startTagEnd, startTagEnd});
        }
        linkToParent(index);
        if (!selfClosing) open_.push_back({index, 0, name});
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

    // Names are interned, so that one written twice has one offset.
    void refuseRepeatedAttributes(const XmlTree::ElementRecord& element) const {
        const XmlTree::AttributeRecord* first = tree_.attributes_.data() + element.firstAttribute;
        for (uint32_t i = 1; i < element.attributeCount; ++i)
            for (uint32_t k = 0; k < i; ++k)
                if (first[i].name == first[k].name) throw NotPlain();
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
        if (open_.empty() || readName() != open_.back().name) throw NotPlain();
        skipBlanks();
        expect('>');
        if (recordSpans_) tree_.spans_[open_.back().element].end = uint64_t(at_ - begin_);
        open_.pop_back();
        return open_.empty();
    }

    // The line of `place`, counted as expat counts: a line feed, a carriage return and the
    // two together each end a line. Places are asked for in document order.
    uint32_t lineAt(const char* place) {
        if (!carriageReturns_) {
            line_ += uint32_t(std::count(counted_, place, '\n'));
        } else {
            for (const char* c = counted_; c < place; ++c)
                if (*c == '\n' || (*c == '\r' && (c + 1 == end_ || c[1] != '\n'))) ++line_;
        }
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
        if (it == names_.end()) it = names_.emplace(name, store(name, false)).first;
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

    const char* const begin_;
    const char* const end_;
    const char* at_;
    const char* counted_;  // lines are counted up to here
    uint32_t line_ = 1;
    int maxDepth_;
    bool recordSpans_;
    bool carriageReturns_;
    XmlTree tree_;
    std::vector<Open> open_;
    std::unordered_map<std::string_view, uint32_t> names_;  // views into the text read
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

}  // namespace ray
