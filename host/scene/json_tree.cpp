// A JSON text into a JsonTree (json_tree.h), through rapidjson's SAX reader.
#include "scene/json_tree.h"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cstring>
#include <limits>
#include <memory>

#include <rapidjson/error/en.h>
#include <rapidjson/memorystream.h>
#include <rapidjson/reader.h>

namespace ray {

const char* jsonKindName(JsonKind kind) {
    switch (kind) {
        case JsonKind::Null: return "null";
        case JsonKind::False:
        case JsonKind::True: return "true or false";
        case JsonKind::Number: return "a number";
        case JsonKind::String: return "a string";
        case JsonKind::Array: return "an array";
        case JsonKind::Object: return "an object";
    }
    return "a value";
}

// rapidjson's handler: each event appends a node and links it to its container. A token's
// place is not in the event, and rapidjson's stream may stand before or after the token
// when it calls the handler (its iterative parser reads ahead), so places are found in the
// text itself: a token starts at the first byte after the end of the one before that is
// neither a blank nor a separator (',' or ':'), and ends after its closing quote, bracket,
// or last character (tokenEnd). rapidjson has checked the syntax: the scan need not.
class JsonTreeBuilder {
public:
    JsonTreeBuilder(JsonTree& tree, std::string_view text, size_t base, int maxDepth)
        : tree_(tree), text_(text), base_(base), maxDepth_(maxDepth) {}

    bool Null() { return scalar(JsonKind::Null); }
    bool Bool(bool b) { return scalar(b ? JsonKind::True : JsonKind::False); }
    bool Int(int i) { return number(double(i)); }
    bool Uint(unsigned u) { return number(double(u)); }
    bool Int64(int64_t i) { return number(double(i)); }
    bool Uint64(uint64_t u) { return number(double(u)); }
    bool Double(double d) { return number(d); }
    // Numbers come as their text (kParseNumbersAsStringsFlag) and are read by from_chars:
    // correctly rounded, as the XML reader's, and without rapidjson 1.1.0's own conversion,
    // which passes 0 to __builtin_clzll on some inputs (internal/diyfp.h).
    bool RawNumber(const char* chars, rapidjson::SizeType length, bool) {
        double value = 0;
        const auto [end, ec] = std::from_chars(chars, chars + length, value);
        if (ec != std::errc() || end != chars + length) {
            stop(JsonError::Kind::Malformed, "the number " + std::string(chars, std::min<size_t>(length, 40)) +
                                                 " is beyond what a double holds");
            return false;
        }
        return number(value);
    }
    bool String(const char* chars, rapidjson::SizeType length, bool) {
        const uint32_t at = uint32_t(tree_.text_.size());
        tree_.text_.insert(tree_.text_.end(), chars, chars + length);
        if (!add(JsonKind::String)) return false;
        JsonTree::Node& node = tree_.nodes_.back();
        node.span.first = at;
        node.span.length = length;
        return true;
    }
    bool Key(const char* chars, rapidjson::SizeType length, bool) {
        const size_t start = tokenStart();
        pendingKeyOffset_ = uint32_t(start);
        pendingKey_ = uint32_t(tree_.text_.size());
        pendingKeyLength_ = length;
        tree_.text_.insert(tree_.text_.end(), chars, chars + length);
        lastEnd_ = tokenEnd(start);
        return true;
    }
    bool StartObject() { return open(JsonKind::Object); }
    bool EndObject(rapidjson::SizeType) { return close(); }
    bool StartArray() { return open(JsonKind::Array); }
    bool EndArray(rapidjson::SizeType) { return close(); }

    // Set when a handler stopped the parse (rapidjson then says kParseErrorTermination).
    const JsonError* error() const { return error_.get(); }

private:
    struct Frame {
        uint32_t index = 0, lastChild = 0;
    };

    size_t tokenStart() const {
        size_t at = lastEnd_;
        while (at < text_.size() && (text_[at] == ' ' || text_[at] == '\t' || text_[at] == '\n' ||
                                     text_[at] == '\r' || text_[at] == ',' || text_[at] == ':'))
            ++at;
        return at;
    }

    // Past the token starting at `start`: a string's closing quote (escapes skipped), a
    // bracket, or a number's or a literal's last character.
    size_t tokenEnd(size_t start) const {
        if (start >= text_.size()) return start;
        const char first = text_[start];
        if (first == '{' || first == '[' || first == '}' || first == ']') return start + 1;
        size_t at = start + 1;
        if (first == '"') {
            while (at < text_.size() && text_[at] != '"') at += text_[at] == '\\' ? 2 : 1;
            return std::min(at + 1, text_.size());
        }
        while (at < text_.size() && !std::strchr(" \t\r\n,:]}", text_[at])) ++at;
        return at;
    }

    bool scalar(JsonKind kind) { return add(kind); }

    bool number(double value) {
        if (!add(JsonKind::Number)) return false;
        tree_.nodes_.back().number = value;
        return true;
    }

    // A new node at the next token.
    bool add(JsonKind kind) {
        if (tree_.nodes_.size() >= std::numeric_limits<uint32_t>::max()) {
            stop(JsonError::Kind::TooLarge, "the file holds more JSON values than ray can read (over 4 billion)");
            return false;
        }
        const uint32_t index = uint32_t(tree_.nodes_.size());
        JsonTree::Node& node = tree_.nodes_.emplace_back();
        node.kind = kind;
        const size_t start = tokenStart();
        node.offset = uint32_t(base_ + start);
        lastEnd_ = tokenEnd(start);
        if (!stack_.empty()) {
            Frame& parent = stack_.back();
            JsonTree::Node& container = tree_.nodes_[parent.index];
            if (container.kind == JsonKind::Object) {
                node.key = pendingKey_;
                node.keyLength = pendingKeyLength_;
                node.keyOffset = uint32_t(base_) + pendingKeyOffset_;
            }
            if (parent.lastChild == 0)
                container.span.first = index;
            else
                tree_.nodes_[parent.lastChild].next = index;
            parent.lastChild = index;
            ++container.span.length;
        }
        return true;
    }

    bool open(JsonKind kind) {
        if (int(stack_.size()) >= maxDepth_) {
            stop(JsonError::Kind::TooDeep, "arrays and objects nested deeper than " + std::to_string(maxDepth_) +
                                               " levels");
            return false;
        }
        if (!add(kind)) return false;
        stack_.push_back({uint32_t(tree_.nodes_.size() - 1), 0});
        return true;
    }

    bool close() {
        stack_.pop_back();
        lastEnd_ = tokenEnd(tokenStart());  // the closing bracket
        return true;
    }

    void stop(JsonError::Kind kind, const std::string& message) {
        error_ = std::make_unique<JsonError>(kind, base_ + tokenStart(), message);
    }

    JsonTree& tree_;
    std::string_view text_;  // after the byte-order mark
    size_t base_;            // the mark's length: offsets are the whole text's
    int maxDepth_;
    size_t lastEnd_ = 0;
    uint32_t pendingKey_ = 0, pendingKeyLength_ = 0, pendingKeyOffset_ = 0;
    std::vector<Frame> stack_;
    std::unique_ptr<JsonError> error_;
};

namespace {

constexpr std::string_view kUtf8Mark = "\xEF\xBB\xBF";

bool startsWith(std::string_view text, std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; }

// A text in UTF-16 or UTF-32 (by its byte-order mark, or the NULs of its first character).
bool looksWide(std::string_view text) {
    return startsWith(text, "\xFF\xFE") || startsWith(text, "\xFE\xFF") ||
           (text.size() >= 2 && (text[0] == '\0' || text[1] == '\0'));
}

}  // namespace

JsonTree JsonTree::parse(std::string_view text, int maxDepth) {
    if (text.size() >= std::numeric_limits<uint32_t>::max())
        throw JsonError(JsonError::Kind::TooLarge, 0, "the file is over 4 GiB");
    if (looksWide(text))
        throw JsonError(JsonError::Kind::Malformed, 0,
                        "the file is in UTF-16 or UTF-32, not UTF-8 (save it as UTF-8)");
    const size_t base = startsWith(text, kUtf8Mark) ? kUtf8Mark.size() : 0;
    const std::string_view body = text.substr(base);
    if (body.find_first_not_of(" \t\r\n") == std::string_view::npos)
        throw JsonError(JsonError::Kind::Empty, 0, "the file is empty");

    JsonTree tree;
    rapidjson::MemoryStream stream(body.data(), body.size());
    JsonTreeBuilder builder(tree, body, base, maxDepth);
    rapidjson::Reader reader;
    constexpr unsigned kFlags =
        rapidjson::kParseIterativeFlag | rapidjson::kParseValidateEncodingFlag | rapidjson::kParseNumbersAsStringsFlag;
    const rapidjson::ParseResult result = reader.Parse<kFlags>(stream, builder);
    if (!result) {
        if (const JsonError* error = builder.error()) throw *error;
        std::string message = rapidjson::GetParseError_En(result.Code());  // "Invalid value."
        if (!message.empty() && message.back() == '.') message.pop_back();
        if (!message.empty()) message[0] = char(std::tolower(static_cast<unsigned char>(message[0])));
        throw JsonError(JsonError::Kind::Malformed, base + result.Offset(), message);
    }
    tree.text_.shrink_to_fit();
    return tree;
}

JsonLines::JsonLines(std::string_view text) : text_(text) {
    lineStarts_.push_back(0);
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') lineStarts_.push_back(i + 1);
}

int JsonLines::line(size_t offset) const {
    return int(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset) - lineStarts_.begin());
}

int JsonLines::column(size_t offset) const {
    size_t start = lineStarts_[size_t(line(offset) - 1)];
    if (start == 0 && text_.substr(0, 3) == "\xEF\xBB\xBF") start = 3;  // the byte-order mark is no character
    int column = 1;
    for (size_t i = start; i < offset && i < text_.size(); ++i)
        if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++column;  // not a UTF-8 continuation byte
    return column;
}

}  // namespace ray
