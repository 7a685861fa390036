#include "edit/node_views.h"

#include "edit/field_values.h"
#include "edit/node_places.h"

namespace ray::edit {

namespace {

const char* csgName(CsgStepKind kind) {
    switch (kind) {
        case CsgStepKind::Union: return "union";
        case CsgStepKind::Intersection: return "intersection";
        case CsgStepKind::Difference: return "difference";
        case CsgStepKind::Operand: break;
    }
    return "operand";
}

OutlineEntry entryOf(SceneDocument& document, const NodePlace& place) {
    OutlineEntry entry{place.id, place.parent, place.depth, nodeKindName(place.id.kind), {}, {}, {}, {}};
    switch (place.id.kind) {
        case NodeKind::Light:
            entry.type = lightTypeName(document.lights[place.index].type);
            entry.text = entry.type + " light";
            break;
        case NodeKind::Tree:
            entry.name = place.tree->name;
            entry.text = entry.name == "root" ? "root" : "master " + entry.name;
            break;
        case NodeKind::Object:
            entry.shape = primitiveTypeName(place.object().type);
            entry.text = entry.shape;
            break;
        case NodeKind::Placement: {
            const MasterReference& master = place.placement();
            entry.text = "master " + master.name;
            auto tree = document.trees.find(master.name);
            if (tree != document.trees.end()) entry.master = NodeId{NodeKind::Tree, tree->second.id};
            break;
        }
        case NodeKind::Csg: entry.text = std::string("csg ") + csgName(place.csg().operation); break;
        case NodeKind::Camera:
        case NodeKind::Globals:
        case NodeKind::Block: break;
    }
    return entry;
}

}  // namespace

std::vector<OutlineEntry> outline(SceneDocument& document) {
    std::vector<OutlineEntry> entries;
    walkNodes(document, [&](const NodePlace& place) {
        entries.push_back(entryOf(document, place));
        return false;
    });
    return entries;
}

NodeView describeNode(SceneDocument& document, const Scene& scene, const NodeId& id) {
    const NodePlace place = requireNode(document, id);
    NodeView view;
    view.entry = entryOf(document, place);
    view.path = place.path;
    for (const EditField* field : fieldsFor(document, place))
        view.fields.emplace_back(field, fieldValue(document, scene, place, *field));
    if (id.kind == NodeKind::Object) {
        const PrimitiveNode& object = place.object();
        view.line = object.line;
        view.ownBlock = place.block().items.size() == 1;
        if (place.tree->name != "root") view.inMaster = NodeId{NodeKind::Tree, place.tree->id};
        for (const auto* list : {&scene.primitives, &scene.csgOperands})
            for (const PrimitiveInstance& instance : *list)
                view.instances += instance.type != PrimitiveType::Csg && instance.sourceObject == object.id ? 1 : 0;
    } else if (id.kind == NodeKind::Tree) {
        view.line = place.tree->line;
    } else if (id.kind == NodeKind::Placement) {
        view.line = place.placement().line;
    } else if (id.kind == NodeKind::Csg) {
        view.line = place.csg().line;
    }
    return view;
}

}  // namespace ray::edit
