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

// The kind of node in the words of the scene's format (OutlineEntry::label).
const char* labelOf(const SceneDocument& document, const NodePlace& place) {
    if (document.format == SceneFormat::Json) {
        switch (place.id.kind) {
            case NodeKind::Tree: return place.tree->name == "root" ? "groups" : "template group";
            case NodeKind::Block: return "group";
            case NodeKind::Placement: return "template use";
            default: break;
        }
    }
    return nodeKindName(place.id.kind);
}

// lightPlaces: jsonLightPlaces(document), for a light.
OutlineEntry entryOf(SceneDocument& document, const NodePlace& place, const std::vector<std::string>& lightPlaces) {
    OutlineEntry entry{place.id, place.parent, place.depth, labelOf(document, place), {}, place.path, {}, {}, {}, {}};
    // An XML scene says "master" before a tree's or a placement's name; a JSON scene's label
    // says what it is already ("template group", "template use").
    const std::string master = document.format == SceneFormat::Json ? "" : "master ";
    switch (place.id.kind) {
        case NodeKind::Light:
            entry.type = lightTypeName(document.lights[place.index].type);
            entry.text = entry.type + " light";
            if (place.index < lightPlaces.size()) entry.path = lightPlaces[place.index];
            break;
        case NodeKind::Tree:
            entry.name = place.tree->name;
            if (entry.name != "root") entry.text = master + entry.name;
            else if (document.format == SceneFormat::Xml) entry.text = "root";
            break;
        case NodeKind::Object:
            entry.shape = primitiveTypeName(place.object().type);
            entry.text = entry.shape;
            break;
        case NodeKind::Placement: {
            const MasterReference& reference = place.placement();
            entry.text = master + reference.name;
            auto tree = document.trees.find(reference.name);
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
    const std::vector<std::string> lightPlaces = jsonLightPlaces(document);
    walkNodes(document, [&](const NodePlace& place) {
        entries.push_back(entryOf(document, place, lightPlaces));
        return false;
    });
    return entries;
}

NodeView describeNode(SceneDocument& document, const Scene& scene, const NodeId& id) {
    const NodePlace place = requireNode(document, id);
    NodeView view;
    view.entry = entryOf(document, place, id.kind == NodeKind::Light ? jsonLightPlaces(document) : std::vector<std::string>{});
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
