#include "edit/node_id.h"

#include <charconv>

namespace ray::edit {

namespace {

// The prefix of each kind's id text, in the order of NodeKind (the camera and the globals
// are their names alone).
constexpr std::string_view kPrefixes[] = {"camera", "globals", "light-", "tree-", "block-", "object-", "placement-",
                                          "csg-"};

}  // namespace

const char* nodeKindName(NodeKind kind) {
    switch (kind) {
        case NodeKind::Camera: return "camera";
        case NodeKind::Globals: return "globals";
        case NodeKind::Light: return "light";
        case NodeKind::Tree: return "tree";
        case NodeKind::Block: return "transblock";
        case NodeKind::Object: return "object";
        case NodeKind::Placement: return "placement";
        case NodeKind::Csg: return "csg";
    }
    return "?";
}

std::string NodeId::text() const {
    const std::string_view prefix = kPrefixes[int(kind)];
    if (kind == NodeKind::Camera || kind == NodeKind::Globals) return std::string(prefix);
    return std::string(prefix) + std::to_string(number);
}

std::optional<NodeId> NodeId::parse(std::string_view text) {
    if (text == "camera") return NodeId{NodeKind::Camera, 0};
    if (text == "globals") return NodeId{NodeKind::Globals, 0};
    for (int kind = int(NodeKind::Light); kind <= int(NodeKind::Csg); ++kind) {
        const std::string_view prefix = kPrefixes[kind];
        if (text.size() <= prefix.size() || text.substr(0, prefix.size()) != prefix) continue;
        const std::string_view digits = text.substr(prefix.size());
        int number = 0;
        const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
        if (error != std::errc() || end != digits.data() + digits.size() || number < 0 || digits[0] == '+')
            return std::nullopt;
        return NodeId{NodeKind(kind), number};
    }
    return std::nullopt;
}

}  // namespace ray::edit
