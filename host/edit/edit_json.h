// The edit model in JSON (docs/modeler-protocol.md): operations read from a request, with
// the text each number was typed as (nlohmann's SAX interface keeps it: a JSON 0.30 is saved
// as 0.30, not 0.3), and the field table, outline, nodes and outcomes written for the page.
// The viewer's routes speak it; its fuzzer reads it.
#pragma once

#include <map>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "edit/edit_error.h"
#include "edit/node_views.h"
#include "edit/operations.h"

namespace ray::edit {

// A JSON document and the text of each of its numbers that is not a whole number, by JSON
// pointer ("/fields/shininess").
struct TypedJson {
    nlohmann::json value;
    std::map<std::string, std::string> typed;
};

// At most this deep (a request is a few levels; the page never nests further).
constexpr size_t kMaxJsonDepth = 32;

// `text` parsed; an empty text is {}. Throws EditError (Type) saying where it is not JSON.
TypedJson parseTypedJson(std::string_view text);

// The longest action id (docs/modeler-protocol.md).
constexpr size_t kMaxActionLength = 64;

// What POST /op asks: the operation, and the action it belongs to (empty: none).
// "camera-from-view" sets the file's camera to `view` (the viewer's), refused without one.
// Throws EditError naming the argument or field that is wrong.
struct JsonOperation {
    Operation operation;
    std::string action;
};
JsonOperation operationFromJson(const TypedJson& request, const Camera* view = nullptr);

// A value for `field` from JSON at `pointer` of `request` (its typed numbers kept). Throws
// EditError (Type) naming the field when the JSON is not of the field's kind.
FieldInput fieldInputFromJson(const EditField& field, const nlohmann::json& value, const TypedJson& request,
                              const std::string& pointer, const std::string& node);

nlohmann::json fieldValueJson(const FieldValue& value);
// GET /fields: {"fields": [...]}.
nlohmann::json fieldTableJson();
// POST /op's "changed", "added", "removed".
nlohmann::json outcomeJson(const Outcome& outcome);
// GET /outline's "nodes".
nlohmann::json outlineJson(const std::vector<OutlineEntry>& entries);
// GET /node.
nlohmann::json nodeJson(const NodeView& view);
// An error's answer: {"error", "field", "node", "exists"}.
nlohmann::json errorJson(const EditError& error);

}  // namespace ray::edit
