// The C++ front end of tests/data/edits/sequence.json (python/tests/test_edit_front_ends.py):
// loads a scene, makes the sequence's edits through the public C++ API (include/ray/scene.h:
// set, add, addLight, remove, duplicate, group, rename, makeUnique), and saves it. The page's
// routes and Python make the same edits; the three files must be the same.
// Usage: edit_sequence SEQUENCE.json SCENE.xml OUT.xml
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ray/ray.h"

namespace {

namespace api = ray::api;
using nlohmann::json;

// "$N.added.K": the K-th node step N added; "@kind.K": the K-th node of that kind in the
// outline (from the end when negative); anything else: itself.
std::string resolve(const std::string& id, const std::vector<api::EditResult>& results, const api::Scene& scene) {
    if (id.empty() || (id[0] != '$' && id[0] != '@')) return id;
    const size_t dot = id.find('.'), last = id.rfind('.');
    if (id[0] == '$') return results.at(std::stoul(id.substr(1, dot - 1))).added.at(std::stoul(id.substr(last + 1)));
    const std::string kind = id.substr(1, dot - 1) == "block" ? "transblock" : id.substr(1, dot - 1);
    std::vector<std::string> nodes;
    for (const api::OutlineEntry& entry : scene.outline())
        if (entry.kind == kind) nodes.push_back(entry.node);
    const long index = std::stol(id.substr(last + 1));
    return nodes.at(size_t(index < 0 ? long(nodes.size()) + index : index));
}

api::FieldValue valueOf(const std::string& name, const json& value) {
    if (value.is_number()) return value.get<double>();
    if (value.is_string()) return value.get<std::string>();
    if (name == "world") {
        api::Transform t;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) t.m[r][c] = value[size_t(4 * r + c)].get<double>();
        return t;
    }
    if (name == "transform") {
        std::vector<api::TransformStep> steps;
        for (const json& step : value) {
            const std::string kind = step["kind"];
            const auto k = kind == "translate" ? api::TransformStep::Kind::Translate
                           : kind == "rotate"  ? api::TransformStep::Kind::Rotate
                           : kind == "scale"   ? api::TransformStep::Kind::Scale
                                               : api::TransformStep::Kind::Matrix;
            steps.push_back({k, step["v"].get<std::vector<double>>()});
        }
        return steps;
    }
    return api::Vec3{value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

api::FieldValues fieldsOf(const json& step) {
    api::FieldValues fields;
    // A local: items() is a view of the object it is given, which must outlive the loop.
    const json given = step.value("fields", json::object());
    for (const auto& [name, value] : given.items()) fields.emplace_back(name, valueOf(name, value));
    return fields;
}

std::vector<std::string> nodesOf(const json& step, const std::vector<api::EditResult>& results, const api::Scene& scene) {
    std::vector<std::string> nodes;
    for (const json& node : step["nodes"]) nodes.push_back(resolve(node, results, scene));
    return nodes;
}

api::EditResult apply(api::Scene& scene, const json& step, const std::vector<api::EditResult>& results,
                      const std::string& folder) {
    const std::string op = step["op"];
    if (op == "set") return scene.set(resolve(step["node"], results, scene), fieldsOf(step));
    if (op == "add-primitive")
        return scene.add(step["shape"], fieldsOf(step), "", step.contains("file") ? folder + "/" + step["file"].get<std::string>() : "");
    if (op == "add-light") return scene.addLight(step["type"], fieldsOf(step));
    if (op == "duplicate") return scene.duplicate(nodesOf(step, results, scene));
    if (op == "group") return scene.group(nodesOf(step, results, scene));
    if (op == "delete") return scene.remove(nodesOf(step, results, scene));
    if (op == "rename") return scene.rename(resolve(step["node"], results, scene), step["name"]);
    if (op == "make-unique") return scene.makeUnique(resolve(step["node"], results, scene));
    throw std::runtime_error("unknown op " + op);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: edit_sequence SEQUENCE.json SCENE.xml OUT.xml\n";
        return 2;
    }
    try {
        const json sequence = json::parse(std::ifstream(argv[1]));
        api::Scene scene = api::Scene::load(argv[2]).scene;
        const std::string folder = std::filesystem::path(argv[2]).parent_path().string();
        std::vector<api::EditResult> results;
        for (const json& step : sequence) results.push_back(apply(scene, step, results, folder));
        scene.save(argv[3]);
    } catch (const std::exception& e) {
        std::cerr << "edit_sequence: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
