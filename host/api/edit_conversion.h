// The public API's edit model (include/ray/scene.h: NodeId, FieldValue, FieldInfo,
// EditResult, OutlineEntry) to and from the editing service's (edit/).
#pragma once

#include "edit/field_table.h"
#include "edit/node_id.h"
#include "edit/node_views.h"
#include "edit/operations.h"
#include "ray/scene.h"

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

// The node `id` names. Throws InputError for an id of no node's form.
ray::edit::NodeId nodeFrom(const NodeId& id);
// The inputs of `fields` for a node of kind `kind`. Throws InputError naming a field the
// node has not, or a value of another kind than the field's.
std::vector<ray::edit::FieldInput> inputsFrom(ray::edit::NodeKind kind, const FieldValues& fields);
std::vector<ray::edit::FieldInput> inputsFrom(ray::edit::FieldOwner owner, const FieldValues& fields);

FieldValue toPublic(const ray::edit::FieldValue& value);
FieldInfo toPublic(const ray::edit::EditField& field);
EditResult toPublic(const ray::edit::Outcome& outcome);
OutlineEntry toPublic(const ray::edit::OutlineEntry& entry);

ray::Affine toInternal(const Transform& t);
Transform toPublic(const ray::Affine& a);

}  // namespace ray::api::detail
#pragma GCC visibility pop
