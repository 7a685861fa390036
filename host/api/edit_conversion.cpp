#include "api/edit_conversion.h"

#include <cmath>

#include "api/camera_conversion.h"
#include "core/message_text.h"
#include "edit/edit_error.h"
#include "edit/field_values.h"

namespace ray::api::detail {

namespace {

[[noreturn]] void badInput(const std::string& what) { throw InputError("error: " + what, "", 0); }

const char* expected(ray::edit::FieldKind kind) {
    using K = ray::edit::FieldKind;
    switch (kind) {
        case K::Number: return "a number (double)";
        case K::Color:
        case K::Vector: return "a Vec3";
        case K::Choice:
        case K::Text:
        case K::File: return "a string";
        case K::Transforms: return "a list of TransformStep";
        case K::Matrix: return "a Transform";
    }
    return "a value";
}

ray::edit::FieldValue internalValue(const ray::edit::EditField& field, const FieldValue& value) {
    using K = ray::edit::FieldKind;
    const std::string name(field.name);
    auto wrong = [&]() -> ray::edit::FieldValue { badInput(name + " takes " + expected(field.kind)); };
    switch (field.kind) {
        case K::Number:
            if (const auto* v = std::get_if<double>(&value)) return *v;
            return wrong();
        case K::Color:
        case K::Vector:
            if (const auto* v = std::get_if<Vec3>(&value)) return toInternal(*v);
            return wrong();
        case K::Choice:
        case K::Text:
        case K::File:
            if (const auto* v = std::get_if<std::string>(&value)) return *v;
            return wrong();
        case K::Matrix:
            if (const auto* v = std::get_if<Transform>(&value)) return toInternal(*v);
            return wrong();
        case K::Transforms: {
            const auto* steps = std::get_if<std::vector<TransformStep>>(&value);
            if (!steps) return wrong();
            std::vector<ray::TransformOp> ops;
            for (const TransformStep& step : *steps) {
                ray::TransformOp op;
                op.kind = ray::TransformKind(int(step.kind));  // same order
                const size_t count = op.kind == ray::TransformKind::Matrix ? 12 : op.kind == ray::TransformKind::Rotate ? 4 : 3;
                if (step.values.size() != count)
                    badInput(name + ": a " + (op.kind == ray::TransformKind::Matrix ? std::string("matrix") : "step") +
                             " of this kind takes " + std::to_string(count) + " numbers, not " +
                             std::to_string(step.values.size()));
                std::copy(step.values.begin(), step.values.end(), op.v.begin());
                ops.push_back(op);
            }
            return ops;
        }
    }
    return wrong();
}

}  // namespace

ray::Affine toInternal(const Transform& t) {
    ray::Affine a;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) a.m[r][c] = t.m[r][c];
    return a;
}

Transform toPublic(const ray::Affine& a) {
    Transform t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = a.m[r][c];
    return t;
}

ray::edit::NodeId nodeFrom(const NodeId& id) {
    std::optional<ray::edit::NodeId> node = ray::edit::NodeId::parse(id);
    if (!node)
        badInput("'" + quotedForMessage(id, 60) + "' names no node (ids are camera, globals, light-N, tree-N, "
                 "block-N, object-N, placement-N, csg-N; Scene::outline lists them)");
    return *node;
}

std::vector<ray::edit::FieldInput> inputsFrom(ray::edit::FieldOwner owner, const FieldValues& fields) {
    std::vector<ray::edit::FieldInput> inputs;
    for (const auto& [name, value] : fields) {
        const ray::edit::EditField* field = ray::edit::findField(owner, name);
        if (!field)
            badInput(std::string("a ") + ray::edit::ownerName(owner) + " has no field '" + quotedForMessage(name, 60) +
                     "' (editableFields() lists them)");
        inputs.push_back({field, internalValue(*field, value), {}});
    }
    return inputs;
}

std::vector<ray::edit::FieldInput> inputsFrom(ray::edit::NodeKind kind, const FieldValues& fields) {
    const std::optional<ray::edit::FieldOwner> owner = ray::edit::fieldOwner(kind);
    if (!owner) badInput(std::string("a ") + ray::edit::nodeKindName(kind) + " has no fields");
    return inputsFrom(*owner, fields);
}

FieldValue toPublic(const ray::edit::FieldValue& value) {
    return std::visit(
        [](const auto& v) -> FieldValue {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<V, double>) return v;
            else if constexpr (std::is_same_v<V, ray::Vec3>) return toPublic(v);
            else if constexpr (std::is_same_v<V, std::string>) return v;
            else if constexpr (std::is_same_v<V, ray::Affine>) return toPublic(v);
            else if constexpr (std::is_same_v<V, ray::edit::ImageHandle>) return "<image " + std::to_string(v.index) + ">";
            else {
                std::vector<TransformStep> steps;
                for (const ray::TransformOp& op : v) {
                    const size_t count = op.kind == ray::TransformKind::Matrix ? 12 : op.kind == ray::TransformKind::Rotate ? 4 : 3;
                    steps.push_back({TransformStep::Kind(int(op.kind)), std::vector<double>(op.v.begin(), op.v.begin() + long(count))});
                }
                return steps;
            }
        },
        value);
}

FieldInfo toPublic(const ray::edit::EditField& field) {
    FieldInfo info;
    info.owner = ray::edit::ownerName(field.owner);
    info.group = field.group;
    info.name = field.name;
    info.keyword = field.keyword();
    info.kind = ray::edit::fieldKindName(field.kind);
    info.help = field.help;
    if (field.rule) {
        info.min = field.rule->low;
        info.max = field.rule->high;
        info.minIncluded = field.rule->lowIncluded;
        info.maxIncluded = field.rule->highIncluded;
    } else {
        info.min = -INFINITY;
        info.max = INFINITY;
    }
    if (field.owner == ray::edit::FieldOwner::Light && field.lights != ~0u)
        for (size_t t = 0; t < ray::edit::lightTypeNames().size(); ++t)
            if (field.appliesTo(ray::LightType(t))) info.lights.emplace_back(ray::edit::lightTypeNames()[t]);
    for (std::string_view choice : field.choices) info.choices.emplace_back(choice);
    return info;
}

EditResult toPublic(const ray::edit::Outcome& outcome) {
    EditResult result;
    result.changed = outcome.changes.names();
    for (const auto& id : outcome.added) result.added.push_back(id.text());
    for (const auto& id : outcome.removed) result.removed.push_back(id.text());
    return result;
}

OutlineEntry toPublic(const ray::edit::OutlineEntry& entry) {
    return {entry.id.text(), entry.parent ? entry.parent->text() : "", entry.depth,
            ray::edit::nodeKindName(entry.id.kind), entry.label, entry.text, entry.path};
}

}  // namespace ray::api::detail
