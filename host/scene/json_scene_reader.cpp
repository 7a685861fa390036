// The course's JSON scenefiles into the scene document (json_scene_reader.h).
#include "scene/json_scene_reader.h"

#include <algorithm>
#include <array>
#include <unordered_map>

#include "scene/json_tree.h"
#include "scene/parameter_rules.h"

namespace ray::loader {
namespace {

// The keys an object of the format may have (SPEC §7): any other fails the file, as in the
// course's reader.
struct KeySet {
    const char* what;  // "a primitive", as the message says it
    std::vector<const char*> keys;
};

const KeySet kSceneKeys{"the scene", {"name", "globalData", "cameraData", "groups", "templateGroups"}};
const KeySet kGlobalKeys{"globalData", {"ambientCoeff", "diffuseCoeff", "specularCoeff", "transparentCoeff"}};
const KeySet kCameraKeys{"cameraData",
                         {"position", "look", "focus", "up", "heightAngle", "aperture", "focalLength"}};
const KeySet kGroupKeys{"a group",
                        {"name", "translate", "rotate", "scale", "matrix", "lights", "primitives", "groups"}};
const KeySet kLightKeys{"a light", {"name", "type", "color", "attenuationCoeff", "direction", "angle", "penumbra"}};
const KeySet kPrimitiveKeys{"a primitive",
                            {"type", "meshFile", "ambient", "diffuse", "specular", "reflective", "transparent",
                             "shininess", "ior", "blend", "textureFile", "textureU", "textureV", "bumpMapFile",
                             "bumpMapU", "bumpMapV"}};
constexpr size_t kMostKeys = 16;

std::string inQuotes(std::string_view text) { return "\"" + quotedForMessage(text) + "\""; }

// "in groups[2].primitives[0]"; the root object's place is empty: "at the top level".
std::string placeText(const std::string& place) { return place.empty() ? "at the top level" : "in " + place; }

// `"diffuse" in groups[2].primitives[0]`
std::string named(const char* key, const std::string& place) { return "\"" + std::string(key) + "\" " + placeText(place); }

std::string item(const std::string& place, const char* array, size_t index) {
    return (place.empty() ? "" : place + ".") + array + "[" + std::to_string(index) + "]";
}

std::string keyList(const KeySet& set) {
    std::string list;
    for (const char* key : set.keys) list += (list.empty() ? "" : ", ") + std::string(key);
    return list;
}

class JsonSceneReader {
public:
    JsonSceneReader(std::string_view text, const Diagnostics& diagnostics, SceneDocument& document)
        : lines_(text), diagnostics_(diagnostics), document_(document) {
        const fs::path folder = document.file.parent_path().empty() ? fs::path(".") : document.file.parent_path();
        // Relative paths are the folder above the scene's; SPEC §1's search then looks
        // under the user's roots, the scene's own folder and its ancestors.
        search_.sceneFolder = folder / "..";
        search_.roots = diagnostics.options().searchPaths;
        search_.roots.push_back(folder);
    }

    void read(const JsonTree& tree) {
        document_.scenefileLine = 1;
        const Members scene(*this, tree.root(), kSceneKeys, "");
        readGlobals(scene.required("globalData", "{\"ambientCoeff\": 0.5, \"diffuseCoeff\": 0.5, \"specularCoeff\": 0.5}"));
        readCamera(scene.required("cameraData", "{\"position\": [...], \"up\": [0, 1, 0], \"heightAngle\": 45, \"look\": [...]}"));
        if (JsonValue name = scene.get("name")) text(name, "name", "");  // the scene's name: checked, unused
        // Templates first, wherever they are written: a group names them by name.
        const JsonValue templates = scene.get("templateGroups");
        if (templates) findTemplates(templates);
        NamedTree& root = addTree("root", scene.get("groups") ? scene.get("groups").keyOffset() : 0);
        if (JsonValue groups = scene.get("groups")) root.tree = readGroups(groups, "groups", "");
        if (templates) readTemplates(templates);
        if (templates && scene.get("groups") && templates.keyOffset() < scene.get("groups").keyOffset())
            rotateRootLast();  // the trees in the file's order: the templates written first
        checkTemplateCycles();
        countInstances(document_.trees, diagnostics_);  // nesting too deep: refused before lights are placed
        placeLights();
    }

private:
    // -----------------------------------------------------------------------------------
    // Messages

    [[noreturn]] void fail(size_t offset, const std::string& problem, const std::string& remedy) const {
        diagnostics_.error(lines_.line(offset), problem, remedy, lines_.column(offset));
    }
    void warn(size_t offset, const std::string& message) const {
        diagnostics_.warning(lines_.line(offset), message, lines_.column(offset));
    }
    int line(size_t offset) const { return lines_.line(offset); }

    // -----------------------------------------------------------------------------------
    // An object's members, every key checked against its set

    class Members {
    public:
        Members(const JsonSceneReader& reader, JsonValue object, const KeySet& keys, std::string place)
            : reader_(reader), object_(object), keys_(keys), place_(std::move(place)) {
            if (!object.isObject())
                reader.fail(object.offset(),
                            (place_.empty() ? std::string("the file") : place_) + " must be an object {...}, not " +
                                jsonKindName(object.kind()),
                            place_.empty() ? "give a CS1230 JSON scene: {\"globalData\": ..., \"cameraData\": ..., "
                                             "\"groups\": [...]}"
                                           : std::string("write ") + keys.what + " as {\"key\": value, ...}");
            for (JsonValue member = object.first(); member; member = member.next()) {
                const size_t index = indexOf(member.key());
                if (index == keys.keys.size())
                    reader.fail(member.keyOffset(),
                                "unknown key " + inQuotes(member.key()) + " " + placeText(place_) + " (" + keys.what +
                                    " has: " + keyList(keys) + ")",
                                "remove it or correct its spelling (the course's reader refuses the whole file too)");
                if (found_[index])
                    reader.fail(member.keyOffset(),
                                "key " + inQuotes(member.key()) + " given twice " + placeText(place_) +
                                    " (first on line " + std::to_string(reader.line(found_[index].keyOffset())) + ")",
                                "keep one of them");
                found_[index] = member;
            }
        }

        // The member's value; false when the key is absent.
        JsonValue get(const char* key) const { return found_[indexOf(key)]; }

        JsonValue required(const char* key, const char* example) const {
            if (JsonValue value = get(key)) return value;
            reader_.fail(object_.offset(), std::string(keys_.what) + " needs \"" + key + "\" " + placeText(place_),
                         std::string("add \"") + key + "\": " + example);
        }

        const std::string& place() const { return place_; }
        size_t offset() const { return object_.offset(); }
        JsonValue value() const { return object_; }

    private:
        size_t indexOf(std::string_view key) const {
            for (size_t i = 0; i < keys_.keys.size(); ++i)
                if (key == keys_.keys[i]) return i;
            return keys_.keys.size();
        }

        const JsonSceneReader& reader_;
        JsonValue object_;
        const KeySet& keys_;
        std::string place_;
        std::array<JsonValue, kMostKeys> found_{};
    };

    // -----------------------------------------------------------------------------------
    // Values

    [[noreturn]] void wrongType(JsonValue value, const char* key, const std::string& place, const std::string& wanted,
                                const std::string& example) const {
        fail(value.offset(), named(key, place) + " must be " + wanted + ", not " + jsonKindName(value.kind()),
             "write it as \"" + std::string(key) + "\": " + example);
    }

    double number(JsonValue value, const char* key, const std::string& place) const {
        if (!value.isNumber()) wrongType(value, key, place, "a number", "1.5");
        return value.number();
    }

    double number(JsonValue value, const char* key, const std::string& place, const NumberRule& rule) const {
        const double result = number(value, key, place);
        if (std::optional<RuleBroken> broken = brokenRule(key, result, rule))
            fail(value.offset(), broken->problem + " (" + named(key, place) + ")", broken->remedy);
        return result;
    }

    // An array of exactly `count` numbers; `usage` names them ("[x, y, z]").
    template <size_t N>
    std::array<double, N> numbers(JsonValue value, const char* key, const std::string& place, const char* usage) const {
        const std::string wanted = "an array of " + std::to_string(N) + " numbers " + usage;
        if (!value.isArray()) wrongType(value, key, place, wanted, usage);
        if (value.size() != N)
            fail(value.offset(),
                 named(key, place) + " must be " + wanted + ", not " + std::to_string(value.size()) + " value" +
                     (value.size() == 1 ? "" : "s"),
                 "write it as \"" + std::string(key) + "\": " + usage);
        std::array<double, N> result{};
        size_t i = 0;
        for (JsonValue element = value.first(); element; element = element.next(), ++i) {
            if (!element.isNumber())
                fail(element.offset(),
                     named(key, place) + " must be " + wanted + ", but value " + std::to_string(i + 1) + " is " +
                         jsonKindName(element.kind()),
                     "write it as \"" + std::string(key) + "\": " + usage);
            result[i] = element.number();
        }
        return result;
    }

    Vec3 vec3(JsonValue value, const char* key, const std::string& place, const char* usage = "[x, y, z]") const {
        const auto v = numbers<3>(value, key, place, usage);
        return {v[0], v[1], v[2]};
    }

    Vec3 vec3(JsonValue value, const char* key, const std::string& place, const NumberRule& rule,
              const char* usage) const {
        const Vec3 result = vec3(value, key, place, usage);
        if (std::optional<RuleBroken> broken = brokenRule(key, result, rule))
            fail(value.offset(), broken->problem + " (" + named(key, place) + ")", broken->remedy);
        return result;
    }

    std::string text(JsonValue value, const char* key, const std::string& place) const {
        if (!value.isString()) wrongType(value, key, place, "a string", "\"...\"");
        return std::string(value.string());
    }

    void expectArray(JsonValue value, const char* key, const std::string& place, const char* example) const {
        if (!value.isArray()) wrongType(value, key, place, "an array", example);
    }

    // -----------------------------------------------------------------------------------
    // globalData, cameraData

    void readGlobals(JsonValue value) {
        const Members m(*this, value, kGlobalKeys, "globalData");
        GlobalCoefficients& g = document_.globals;
        g.ka = number(m.required("ambientCoeff", "0.5"), "ambientCoeff", m.place(), rules::kFinite);
        g.kd = number(m.required("diffuseCoeff", "0.5"), "diffuseCoeff", m.place(), rules::kFinite);
        g.ks = number(m.required("specularCoeff", "0.5"), "specularCoeff", m.place(), rules::kFinite);
        const JsonValue kt = m.get("transparentCoeff");
        g.kt = kt ? number(kt, "transparentCoeff", m.place(), rules::kFinite) : 0.0;
    }

    void readCamera(JsonValue value) {
        const Members m(*this, value, kCameraKeys, "cameraData");
        Camera& camera = document_.camera;
        camera.position = vec3(m.required("position", "[x, y, z]"), "position", m.place());
        camera.up = vec3(m.required("up", "[0, 1, 0]"), "up", m.place());
        camera.heightAngleDegrees =
            number(m.required("heightAngle", "45"), "heightAngle", m.place(), rules::kHeightAngle);
        const JsonValue look = m.get("look"), focus = m.get("focus");
        if (look && focus)
            fail(std::max(look.keyOffset(), focus.keyOffset()), "the camera has both \"look\" and \"focus\"",
                 "keep one: look is a direction, focus is a point to look at");
        if (!look && !focus)
            fail(m.offset(), "the camera has neither \"look\" nor \"focus\" (cameraData)",
                 "add \"look\": [x, y, z] (a direction) or \"focus\": [x, y, z] (a point to look at)");
        camera.look = look ? vec3(look, "look", m.place()) : vec3(focus, "focus", m.place()) - camera.position;
        if (JsonValue aperture = m.get("aperture")) camera.aperture = number(aperture, "aperture", m.place(), rules::kFinite);
        if (JsonValue focal = m.get("focalLength")) camera.focalLength = number(focal, "focalLength", m.place(), rules::kFinite);
        if (std::optional<RuleBroken> broken =
                brokenCameraAxes(camera, "\"look\", or a \"focus\" point away from \"position\"", "\"up\""))
            fail(m.offset(), broken->problem, broken->remedy);
    }

    // -----------------------------------------------------------------------------------
    // Templates

    struct Template {
        JsonValue value;
        std::string place;
    };

    // Every template's name, before any group is read (a group names a template written
    // after it as well as before).
    void findTemplates(JsonValue templates) {
        expectArray(templates, "templateGroups", "", "[{\"name\": \"...\", ...}]");
        size_t index = 0;
        for (JsonValue value = templates.first(); value; value = value.next(), ++index) {
            const std::string place = item("", "templateGroups", index);
            const Members m(*this, value, kGroupKeys, place);
            const JsonValue nameValue = m.required("name", "\"a name the groups that place it give\"");
            const std::string name = text(nameValue, "name", place);
            if (name == "root")
                fail(nameValue.offset(), "a template named \"root\" (" + place + ")",
                     "rename it: ray's scene document names the scene itself \"root\"");
            auto [it, added] = templates_.try_emplace(name, Template{value, place});
            if (!added)
                fail(nameValue.offset(),
                     "a second template named " + inQuotes(name) + " (" + place + "; the first is " + it->second.place +
                         ", line " + std::to_string(line(it->second.value.offset())) + ")",
                     "give each template its own name");
        }
    }

    void readTemplates(JsonValue templates) {
        size_t index = 0;
        for (JsonValue value = templates.first(); value; value = value.next(), ++index) {
            const std::string place = item("", "templateGroups", index);
            const std::string name(Members(*this, value, kGroupKeys, place).get("name").string());
            NamedTree& tree = addTree(name, value.offset());
            currentTemplate_ = name;
            tree.tree.blocks.push_back(readGroup(value, place, true));
            currentTemplate_.clear();
        }
    }

    void rotateRootLast() {
        std::vector<std::string>& order = document_.treeOrder;
        std::rotate(order.begin(), order.begin() + 1, order.end());  // "root" is added first
    }

    NamedTree& addTree(const std::string& name, size_t offset) {
        NamedTree& tree = document_.trees[name];
        tree.name = name;
        tree.line = offset ? line(offset) : 1;
        document_.treeOrder.push_back(name);
        return tree;
    }

    // A template that contains itself, directly or through others, is found from the
    // references each template makes (walked without recursion: a chain of templates may
    // be long), before anything follows them.
    void checkTemplateCycles() const {
        enum class Mark { New, Open, Done };
        std::map<std::string, Mark> marks;
        for (const auto& [start, unused] : references_) {
            if (marks[start] != Mark::New) continue;
            struct Step {
                std::string name;
                size_t next = 0;
            };
            std::vector<Step> path{{start, 0}};
            marks[start] = Mark::Open;
            while (!path.empty()) {
                Step& step = path.back();
                auto edges = references_.find(step.name);
                if (edges == references_.end() || step.next == edges->second.size()) {
                    marks[step.name] = Mark::Done;
                    path.pop_back();
                    continue;
                }
                const Reference& reference = edges->second[step.next++];
                Mark& mark = marks[reference.name];
                if (mark == Mark::Open) reportCycle(path, reference);
                if (mark == Mark::New) {
                    mark = Mark::Open;
                    path.push_back({reference.name, 0});
                }
            }
        }
    }

    struct Reference {
        std::string name;  // the template placed
        size_t offset = 0;
    };

    template <class Path>
    [[noreturn]] void reportCycle(const Path& path, const Reference& reference) const {
        std::string cycle;
        bool inCycle = false;
        for (const auto& step : path) {
            inCycle = inCycle || step.name == reference.name;
            if (inCycle) cycle += inQuotes(step.name) + " -> ";
        }
        cycle += inQuotes(reference.name);
        fail(reference.offset, "template " + inQuotes(reference.name) + " contains itself: " + cycle,
             "a template cannot contain itself, directly or through other templates; remove one of these groups");
    }

    // -----------------------------------------------------------------------------------
    // Groups

    // The blocks of a "groups" array.
    TreeNode readGroups(JsonValue groups, const char* key, const std::string& place) {
        expectArray(groups, key, place, "[{...}, ...]");
        TreeNode tree;
        tree.source = groups.index();
        tree.blocks.reserve(groups.size());
        size_t index = 0;
        for (JsonValue group = groups.first(); group; group = group.next(), ++index)
            tree.blocks.push_back(readGroup(group, item(place, key, index), false));
        return tree;
    }

    // A group: its transforms (T, R, S, Matrix), its primitives, its subgroups; its lights
    // kept for placing (placeLights). A group named as a template is that template.
    Block readGroup(JsonValue value, const std::string& place, bool definesTemplate) {
        const Members m(*this, value, kGroupKeys, place);
        Block block;
        block.id = document_.nextBlockId++;
        block.source = value.index();
        const JsonValue name = m.get("name");
        const std::string groupName = name ? text(name, "name", place) : std::string();
        if (!definesTemplate && templates_.count(groupName)) {
            block.items.push_back(templatePlacement(m, name, groupName));
            return block;
        }
        readTransforms(m, block);
        if (JsonValue lights = m.get("lights")) readLights(lights, place, block.id);
        if (JsonValue primitives = m.get("primitives")) {
            expectArray(primitives, "primitives", place, "[{\"type\": \"cube\", ...}]");
            block.items.reserve(primitives.size() + 1);
            size_t index = 0;
            for (JsonValue primitive = primitives.first(); primitive; primitive = primitive.next(), ++index)
                block.items.push_back(readPrimitive(primitive, item(place, "primitives", index)));
        }
        if (JsonValue groups = m.get("groups")) {
            TreeNode subgroups = readGroups(groups, "groups", place);
            if (!subgroups.blocks.empty()) block.items.push_back(Box<TreeNode>(std::move(subgroups)));
        }
        return block;
    }

    MasterReference templatePlacement(const Members& m, JsonValue name, const std::string& groupName) {
        for (const char* key : kGroupKeys.keys)
            if (std::string_view(key) != "name" && m.get(key))
                warn(m.get(key).offset(), named(key, m.place()) + " is ignored: a group named " + inQuotes(groupName) +
                                              " is that template (put the template in a group of its own to "
                                              "transform it)");
        MasterReference reference;
        reference.name = groupName;
        reference.line = line(name.offset());
        reference.source = m.value().index();
        references_[currentTemplate_.empty() ? "root" : currentTemplate_].push_back({groupName, name.offset()});
        return reference;
    }

    // M = T · R · S · Matrix, whatever the order of the keys: a point is scaled first.
    void readTransforms(const Members& m, Block& block) const {
        if (JsonValue translate = m.get("translate"))
            block.transforms.push_back(transform(TransformKind::Translate, vec3(translate, "translate", m.place())));
        if (JsonValue rotate = m.get("rotate")) {
            const auto v = numbers<4>(rotate, "rotate", m.place(), "[x, y, z, degrees]");
            TransformOp op;
            op.kind = TransformKind::Rotate;
            std::copy(v.begin(), v.end(), op.v.begin());
            checkInvertible(op, rotate, "give the axis to rotate about, such as [0, 1, 0, 45]");
            block.transforms.push_back(op);
        }
        if (JsonValue scale = m.get("scale")) {
            const TransformOp op = transform(TransformKind::Scale, vec3(scale, "scale", m.place()));
            checkInvertible(op, scale, "use a small non-zero factor, or remove the group");
            block.transforms.push_back(op);
        }
        if (JsonValue matrix = m.get("matrix")) block.transforms.push_back(readMatrix(matrix, m.place()));
        composeBlock(block);
    }

    static TransformOp transform(TransformKind kind, const Vec3& xyz) {
        TransformOp op;
        op.kind = kind;
        op.v[0] = xyz.x, op.v[1] = xyz.y, op.v[2] = xyz.z;
        return op;
    }

    void checkInvertible(const TransformOp& op, JsonValue value, const char* remedy) const {
        if (std::optional<std::string> why = op.whySingular()) fail(value.offset(), *why, remedy);
    }

    // Four rows of four numbers, as written: the translation is the last column.
    TransformOp readMatrix(JsonValue value, const std::string& place) const {
        const char* usage = "[[a, b, c, tx], [d, e, f, ty], [g, h, i, tz], [0, 0, 0, 1]]";
        if (!value.isArray()) wrongType(value, "matrix", place, "an array of 4 rows of 4 numbers", usage);
        if (value.size() != 4)
            fail(value.offset(), named("matrix", place) + " has " + std::to_string(value.size()) + " rows, not 4",
                 std::string("write it as \"matrix\": ") + usage);
        Affine m;
        std::array<double, 4> last{};
        int r = 0;
        for (JsonValue row = value.first(); row; row = row.next(), ++r) {
            const auto numbers4 = numbers<4>(row, "matrix", place, "[v1, v2, v3, v4] for each row");
            if (r < 3)
                for (int c = 0; c < 4; ++c) m.m[r][c] = numbers4[size_t(c)];
            else
                last = numbers4;
        }
        if (last != std::array<double, 4>{0, 0, 0, 1})
            fail(value.offset(), "the matrix's last row is not [0, 0, 0, 1] (" + named("matrix", place) + ")",
                 "give an affine transform (translation in the last column)");
        TransformOp op = TransformOp::matrix(m);
        checkInvertible(op, value, "give an invertible matrix");
        return op;
    }

    // -----------------------------------------------------------------------------------
    // Lights: read in the group's frame, placed by placeLights.

    void readLights(JsonValue lights, const std::string& place, int blockId) {
        expectArray(lights, "lights", place, "[{\"type\": \"point\", ...}]");
        size_t index = 0;
        for (JsonValue value = lights.first(); value; value = value.next(), ++index)
            localLights_[blockId].push_back({readLight(value, item(place, "lights", index)), value.index()});
    }

    Light readLight(JsonValue value, const std::string& place) const {
        const Members m(*this, value, kLightKeys, place);
        Light light;
        const JsonValue typeValue = m.required("type", "\"point\" (or \"directional\", \"spot\")");
        const std::string type = text(typeValue, "type", place);
        if (type == "point")
            light.type = LightType::Point;
        else if (type == "directional")
            light.type = LightType::Directional;
        else if (type == "spot")
            light.type = LightType::Spot;
        else
            fail(typeValue.offset(), "unknown light type " + inQuotes(type) + " (" + place + ")",
                 type == "area" ? "a JSON scene has no area lights (an XML scene has); use point, directional or spot"
                                : "use point, directional or spot");
        if (JsonValue name = m.get("name")) text(name, "name", place);  // allowed, unused
        light.color = vec3(m.required("color", "[r, g, b]"), "color", place, rules::kColorChannel, "[r, g, b]");
        light.position = {0, 0, 0};  // in the group's frame
        const bool positioned = light.type != LightType::Directional, aimed = light.type != LightType::Point;
        const JsonValue attenuation = positioned ? m.required("attenuationCoeff", "[1, 0, 0]") : m.get("attenuationCoeff");
        if (attenuation)
            light.attenuation = vec3(attenuation, "attenuationCoeff", place, rules::kAttenuation, "[c1, c2, c3]");
        const JsonValue direction = aimed ? m.required("direction", "[x, y, z]") : m.get("direction");
        if (direction) light.direction = vec3(direction, "direction", place);
        const bool spot = light.type == LightType::Spot;
        const JsonValue angle = spot ? m.required("angle", "30 (degrees)") : m.get("angle");
        if (angle) light.angleDegrees = number(angle, "angle", place, rules::kSpotAngle);
        const JsonValue penumbra = spot ? m.required("penumbra", "5 (degrees)") : m.get("penumbra");
        if (penumbra) light.penumbraDegrees = number(penumbra, "penumbra", place, rules::kPenumbra);
        return light;
    }

    // Every light, in world space: once for each placement of the groups holding it, in
    // the groups' order. Only trees that hold lights are walked (a scene of millions of
    // instances may have two lights).
    void placeLights() {
        NamedTree& root = document_.trees.at("root");
        const uint64_t total = lightsIn(root.tree);
        if (total > kMaxJsonLights)
            fail(0, "the scene places " + std::to_string(total) + " lights, more than the " +
                        std::to_string(kMaxJsonLights) + " ray takes",
                 "place the templates that hold lights fewer times");
        document_.lights.reserve(size_t(total));
        document_.lightSources.reserve(size_t(total));
        placeLights(root.tree, Affine::identity());
    }

    uint64_t lightsIn(const TreeNode& tree) {
        auto [it, added] = lightCounts_.try_emplace(&tree, 0);
        if (!added) return it->second;
        uint64_t count = 0;
        for (const Block& block : tree.blocks) {
            auto own = localLights_.find(block.id);
            if (own != localLights_.end()) count += own->second.size();
            for (const SceneItem& item : block.items) count = std::min<uint64_t>(count + lightsIn(item), kMaxJsonLights + 1);
        }
        lightCounts_[&tree] = count;
        return count;
    }

    uint64_t lightsIn(const SceneItem& item) {
        if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) return lightsIn(**subtree);
        if (auto* reference = std::get_if<MasterReference>(&item)) return lightsIn(document_.trees.at(reference->name).tree);
        return 0;
    }

    void placeLights(const TreeNode& tree, const Affine& parent) {
        for (const Block& block : tree.blocks) {
            const Affine frame = parent * block.toParent;
            auto own = localLights_.find(block.id);
            if (own != localLights_.end())
                for (auto [light, source] : own->second) {
                    light.position = frame.transformPoint(light.position);
                    light.direction = frame.transformVector(light.direction);
                    document_.lights.push_back(light);
                    document_.lightSources.push_back(source);  // a template's light: one value, placed each time
                }
            for (const SceneItem& item : block.items) {
                if (lightsIn(item) == 0) continue;
                if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) placeLights(**subtree, frame);
                else if (auto* reference = std::get_if<MasterReference>(&item))
                    placeLights(document_.trees.at(reference->name).tree, frame);
            }
        }
    }

    // -----------------------------------------------------------------------------------
    // Primitives

    PrimitiveNode readPrimitive(JsonValue value, const std::string& place) {
        const Members m(*this, value, kPrimitiveKeys, place);
        ++document_.primitiveElements;
        PrimitiveNode node;
        node.source = value.index();
        node.line = line(value.offset());
        node.id = document_.nextObjectId++;
        const JsonValue typeValue = m.required("type", "\"cube\" (or sphere, cylinder, cone, mesh)");
        node.type = primitiveType(typeValue, place);
        if (node.type == PrimitiveType::Mesh) {
            const JsonValue file = m.required("meshFile", "\"meshes/file.obj\"");
            const std::string written = text(file, "meshFile", place);
            node.filesToSet().meshFile = resolveMesh(file, written);
            node.files->meshWritten = written;
        } else if (JsonValue file = m.get("meshFile")) {
            text(file, "meshFile", place);  // allowed, unused
        }
        Material& material = node.material;
        const std::pair<const char*, Vec3*> colors[] = {{"ambient", &material.ambient},
                                                        {"diffuse", &material.diffuse},
                                                        {"specular", &material.specular},
                                                        {"reflective", &material.reflective},
                                                        {"transparent", &material.transparent}};
        for (const auto& [key, target] : colors)
            if (JsonValue color = m.get(key)) *target = vec3(color, key, place, rules::kColorChannel, "[r, g, b]");
        if (JsonValue v = m.get("shininess")) material.shininess = number(v, "shininess", place, rules::kShininess);
        if (JsonValue v = m.get("ior")) material.ior = number(v, "ior", place, rules::kIor);
        if (JsonValue v = m.get("blend")) material.blend = number(v, "blend", place, rules::kBlend);
        readImage(m, "textureFile", "textureU", "textureV", "texture", material.texture, node,
                  &PrimitiveFiles::texture, &PrimitiveFiles::missingTexture);
        readImage(m, "bumpMapFile", "bumpMapU", "bumpMapV", "bump map", material.bumpMap, node,
                  &PrimitiveFiles::bumpMap, &PrimitiveFiles::missingBumpMap);
        return node;
    }

    PrimitiveType primitiveType(JsonValue value, const std::string& place) const {
        static const std::pair<const char*, PrimitiveType> kTypes[] = {
            {"cube", PrimitiveType::Cube},
            {"sphere", PrimitiveType::Sphere},
            {"cylinder", PrimitiveType::Cylinder},
            {"cone", PrimitiveType::Cone},
            {"mesh", PrimitiveType::Mesh},
        };
        const std::string type = text(value, "type", place);
        for (const auto& [name, known] : kTypes)
            if (type == name) return known;
        fail(value.offset(), "unknown primitive type " + inQuotes(type) + " (" + place + ")",
             type == "torus" ? "a JSON scene has no torus (an XML scene has); use cube, sphere, cylinder, cone or mesh"
                             : "use cube, sphere, cylinder, cone or mesh");
    }

    fs::path resolveMesh(JsonValue value, const std::string& reference) const {
        std::vector<fs::path> tried;
        if (std::optional<fs::path> found = search_.resolve(reference, &tried)) return *found;
        fail(value.offset(),
             "mesh file '" + reference + "' not found (" + whereLooked(reference, tried, search_) + ")",
             "put the OBJ file there, or name its folder with a search path");
    }

    // A texture or bump map: the file, resolved (a missing one warns, once per name, and
    // the surface keeps its material colors) and its repeats (1 each by default).
    void readImage(const Members& m, const char* fileKey, const char* uKey, const char* vKey, const char* what,
                   TextureMap& map, PrimitiveNode& node, std::optional<ImageReference> PrimitiveFiles::*found,
                   std::string PrimitiveFiles::*missing) {
        if (JsonValue u = m.get(uKey)) map.repeatU = number(u, uKey, m.place(), rules::kFinite);
        if (JsonValue v = m.get(vKey)) map.repeatV = number(v, vKey, m.place(), rules::kFinite);
        const JsonValue file = m.get(fileKey);
        if (!file) return;
        const std::string reference = text(file, fileKey, m.place());
        if (reference.find_first_not_of(" \t\r\n") == std::string::npos) {
            warn(file.offset(), std::string(what) + " without a file name (" + named(fileKey, m.place()) +
                                    "); it is ignored");
            return;
        }
        std::optional<ImageReference> image = resolveImage(file, reference, what);
        if (image)
            node.filesToSet().*found = std::move(image);
        else
            node.filesToSet().*missing = reference;
    }

    std::optional<ImageReference> resolveImage(JsonValue file, const std::string& reference, const char* what) {
        auto [known, isNew] = resolvedImages_.try_emplace(reference);
        if (isNew) {
            std::vector<fs::path> tried;
            known->second = search_.resolve(reference, &tried);
            if (!known->second) {
                if (auto special = firstNonRegular(tried))
                    warn(file.offset(), std::string(what) + " file " + special->string() +
                                            " is not a regular file (a FIFO, device or folder: reading it could block "
                                            "or never end); it is not read, and the surface keeps its material colors");
                else
                    warn(file.offset(), std::string(what) + " file '" + reference + "' not found (" +
                                            whereLooked(reference, tried, search_) +
                                            "); the surface keeps its material colors");
            }
        }
        if (!known->second) return std::nullopt;
        return ImageReference{*known->second, line(file.offset()), reference};
    }

    const JsonLines lines_;
    const Diagnostics& diagnostics_;
    SceneDocument& document_;
    FileSearch search_;
    std::map<std::string, Template> templates_;
    std::string currentTemplate_;  // the template being read; empty in the scene's groups
    std::map<std::string, std::vector<Reference>> references_;  // by the tree ("root" or a template) making them
    // By block id, in the block's frame, with the value each was read from.
    std::unordered_map<int, std::vector<std::pair<Light, SourceId>>> localLights_;
    std::unordered_map<const TreeNode*, uint64_t> lightCounts_;
    std::map<std::string, std::optional<fs::path>> resolvedImages_;  // by reference as written
};

// What is wrong with the JSON text, in the loader's words.
[[noreturn]] void reportSyntax(const JsonError& error, std::string_view text, const Diagnostics& diagnostics) {
    const JsonLines lines(text);
    const int line = lines.line(error.offset), column = lines.column(error.offset);
    switch (error.kind) {
        case JsonError::Kind::Empty:
            diagnostics.error(0, "the file is empty",
                              "give a CS1230 JSON scene ({\"globalData\": ..., \"cameraData\": ..., \"groups\": [...]})");
        case JsonError::Kind::TooDeep:
            diagnostics.error(line, error.what(), "flatten the hierarchy (fewer levels of nested groups)", column);
        case JsonError::Kind::TooLarge:
            diagnostics.error(line, error.what(), "split the scene, or place repeated parts with templates", column);
        case JsonError::Kind::Malformed:
            break;
    }
    diagnostics.error(line, std::string("malformed JSON: ") + error.what(), "fix the JSON syntax there", column);
}

}  // namespace

void readJsonSceneDocument(std::string_view text, const Diagnostics& diagnostics, SceneDocument& document) {
    JsonTree tree;
    try {
        tree = JsonTree::parse(text, kMaxJsonDepth);
    } catch (const JsonError& error) {
        reportSyntax(error, text, diagnostics);
    }
    JsonSceneReader(text, diagnostics, document).read(tree);
}

}  // namespace ray::loader
