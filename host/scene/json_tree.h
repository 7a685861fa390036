// A JSON text as a compact, read-only tree of values, each with its byte offset in the text,
// built by rapidjson's SAX reader (Debian: rapidjson-dev).
//
// The course's JSON scenefiles (SPEC §7) are read in two steps: the text into this tree
// (syntax: what any JSON reader refuses), then the tree into a scene document
// (json_scene_reader.h: the format's rules). Every value keeps where it starts, and every
// object member where its key starts, so that a message names line and column
// (JsonLines), and a later save can find what to keep of the text.
//
// What a hostile file can make the tree hold is bounded by its size: 32 bytes a value
// (a value is at least one byte of text and its separator), the strings' bytes once, and
// nesting deeper than the limit given to parse is refused before anything walks it. rapidjson
// parses iteratively (kParseIterativeFlag), so deep nesting never recurses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ray {

// Why a text is not a JSON tree: what() says what is wrong, in words, without the file's
// name; offset is the byte where it was found.
class JsonError : public std::runtime_error {
public:
    enum class Kind { Empty, Malformed, TooDeep, TooLarge };
    JsonError(Kind kind, size_t offset, const std::string& message)
        : std::runtime_error(message), kind(kind), offset(offset) {}
    Kind kind;
    size_t offset;
};

enum class JsonKind : uint8_t { Null, False, True, Number, String, Array, Object };

// The JSON type's name as a message says it ("a number", "an array").
const char* jsonKindName(JsonKind kind);

class JsonTree;

// A value of a JsonTree: a handle (the tree and an index), cheap to copy, valid while the
// tree lives. A default-constructed one names no value and converts to false.
class JsonValue {
public:
    JsonValue() = default;
    explicit operator bool() const { return tree_ != nullptr; }

    JsonKind kind() const;
    bool isNumber() const { return kind() == JsonKind::Number; }
    bool isString() const { return kind() == JsonKind::String; }
    bool isArray() const { return kind() == JsonKind::Array; }
    bool isObject() const { return kind() == JsonKind::Object; }

    size_t offset() const;  // of its first byte in the text
    // Its place in the tree (JsonTree::at gives it back): document order, the root 0.
    uint32_t index() const { return index_; }
    double number() const;  // numbers only
    std::string_view string() const;  // strings only (may hold NULs: JSON's \u0000)
    // Arrays and objects: the number of items or members, the first, and (of an item or a
    // member) the next; false when there is none.
    size_t size() const;
    JsonValue first() const;
    JsonValue next() const;
    // Of an object's member: its key and where the key starts.
    std::string_view key() const;
    size_t keyOffset() const;

private:
    friend class JsonTree;
    friend class JsonTreeBuilder;
    JsonValue(const JsonTree* tree, uint32_t index) : tree_(tree), index_(index) {}
    const JsonTree* tree_ = nullptr;
    uint32_t index_ = 0;
};

class JsonTree {
public:
    // Parses `text` (UTF-8, a byte-order mark allowed). Containers nested deeper than
    // maxDepth are refused (JsonError::Kind::TooDeep). Throws JsonError.
    static JsonTree parse(std::string_view text, int maxDepth);

    JsonTree() = default;
    JsonTree(JsonTree&&) = default;
    JsonTree& operator=(JsonTree&&) = default;
    JsonTree(const JsonTree&) = delete;  // handles point at the tree
    JsonTree& operator=(const JsonTree&) = delete;

    JsonValue root() const { return nodes_.empty() ? JsonValue() : JsonValue(this, 0); }
    // The value at `index` (JsonValue::index); none past the last.
    JsonValue at(uint32_t index) const { return index < nodes_.size() ? JsonValue(this, index) : JsonValue(); }
    size_t valueCount() const { return nodes_.size(); }

private:
    friend class JsonValue;
    friend class JsonTreeBuilder;

    // Values in document order (a container before its contents), so index 0 is the root
    // and never a child or a sibling: 0 in firstChild or next means "none". Strings and
    // keys are bytes in text_, addressed by offset and length.
    struct Node {
        uint32_t offset = 0;     // in the text
        uint32_t keyOffset = 0;  // in the text, for an object's member
        uint32_t key = 0, keyLength = 0;  // in text_, for an object's member
        uint32_t next = 0;
        JsonKind kind = JsonKind::Null;
        union {
            double number;
            struct {
                uint32_t first;   // String: in text_; Array, Object: the first child
                uint32_t length;  // String: bytes; Array, Object: children
            } span;
        };
        Node() : span{0, 0} {}
    };

    std::vector<Node> nodes_;
    std::vector<char> text_;
};

// Line and column (both 1-based; the column counts characters, not bytes) of byte offsets
// in a text, each found in O(log lines).
class JsonLines {
public:
    explicit JsonLines(std::string_view text);
    int line(size_t offset) const;
    int column(size_t offset) const;

private:
    std::string_view text_;
    std::vector<size_t> lineStarts_;
};

// ---------------------------------------------------------------------------------------

inline JsonKind JsonValue::kind() const { return tree_->nodes_[index_].kind; }
inline size_t JsonValue::offset() const { return tree_->nodes_[index_].offset; }
inline double JsonValue::number() const { return tree_->nodes_[index_].number; }
inline std::string_view JsonValue::string() const {
    const auto& node = tree_->nodes_[index_];
    return {tree_->text_.data() + node.span.first, node.span.length};
}
inline size_t JsonValue::size() const { return tree_->nodes_[index_].span.length; }
inline JsonValue JsonValue::first() const {
    const auto& node = tree_->nodes_[index_];
    return node.span.length ? JsonValue(tree_, node.span.first) : JsonValue();
}
inline JsonValue JsonValue::next() const {
    const uint32_t next = tree_->nodes_[index_].next;
    return next ? JsonValue(tree_, next) : JsonValue();
}
inline std::string_view JsonValue::key() const {
    const auto& node = tree_->nodes_[index_];
    return {tree_->text_.data() + node.key, node.keyLength};
}
inline size_t JsonValue::keyOffset() const { return tree_->nodes_[index_].keyOffset; }

}  // namespace ray
