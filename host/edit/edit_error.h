// Why an edit was refused: a plain sentence that names the field (or the argument) it is
// about. Every front end says it in its own way from these parts: the viewer as HTTP 400
// (409 for a name in use) with the sentence, the field and the node; the C++ API as an
// InputError; Python as a ValueError, or a TypeError for a value of the wrong type or shape.
#pragma once

#include <stdexcept>
#include <string>

namespace ray::edit {

struct EditError : std::invalid_argument {
    enum class Kind {
        Value,   // out of range, not finite, singular, a node that does not exist
        Type,    // the wrong type or shape: a string for a number, two numbers for a color
        Exists,  // a name already in use
    };
    EditError(const std::string& message, Kind kind = Kind::Value, std::string field = {}, std::string node = {})
        : std::invalid_argument(message), kind(kind), field(std::move(field)), node(std::move(node)) {}

    Kind kind;
    std::string field;  // the field's scenefile name, when the error is one field's
    std::string node;   // the node's id text ("object-3"), when the error is one node's
};

}  // namespace ray::edit
