// The course reader's key rules for a JSON scenefile (SPEC §7), checked apart from ray's own
// reader (scene/json_scene_reader.h), so that what ray writes is held to the spec and not
// to what ray's reader happens to take: each object's allowed and required keys, the types
// and lengths of values, no key twice, and a template placed inside another defined before
// it (the course's reader looks only backwards).
#pragma once

#include <nlohmann/json.hpp>

#include <set>
#include <string>
#include <vector>

namespace ray::test {

class CourseJsonRules {
public:
    // What in `text` the course's reader would refuse; empty when it reads it.
    static std::vector<std::string> breaches(const std::string& text) {
        CourseJsonRules rules;
        rules.check(text);
        return rules.breaches_;
    }

private:
    using json = nlohmann::json;

    void fail(const std::string& place, const std::string& what) { breaches_.push_back(place + ": " + what); }

    void check(const std::string& text) {
        std::vector<std::set<std::string>> open;
        json root;
        try {
            root = json::parse(text, [&](int, json::parse_event_t event, json& parsed) {
                if (event == json::parse_event_t::object_start) open.emplace_back();
                else if (event == json::parse_event_t::object_end) open.pop_back();
                else if (event == json::parse_event_t::key && !open.back().insert(parsed.get<std::string>()).second)
                    fail("an object", "key \"" + parsed.get<std::string>() + "\" given twice");
                return true;
            });
        } catch (const json::exception& e) {
            fail("the file", std::string("not JSON: ") + e.what());
            return;
        }
        if (!keys(root, "the scene", {"name", "globalData", "cameraData", "groups", "templateGroups"},
                  {"globalData", "cameraData"}))
            return;
        if (root.contains("name")) string(root["name"], "name");
        const json& globals = root["globalData"];
        if (keys(globals, "globalData", {"ambientCoeff", "diffuseCoeff", "specularCoeff", "transparentCoeff"},
                 {"ambientCoeff", "diffuseCoeff", "specularCoeff"}))
            for (const auto& [key, value] : globals.items()) number(value, "globalData." + key);
        camera(root["cameraData"]);
        if (root.contains("templateGroups") && array(root["templateGroups"], "templateGroups")) {
            for (const json& group : root["templateGroups"])
                if (group.is_object() && group.contains("name") && group["name"].is_string())
                    allTemplates_.insert(group["name"].get<std::string>());
            inTemplate_ = true;
            for (size_t i = 0; i < root["templateGroups"].size(); ++i) {
                const json& group = root["templateGroups"][i];
                const std::string place = "templateGroups[" + std::to_string(i) + "]";
                if (!group.is_object() || !group.contains("name")) fail(place, "a template without a name");
                this->group(group, place, true);
                if (group.is_object() && group.contains("name") && group["name"].is_string())
                    defined_.insert(group["name"].get<std::string>());
            }
            inTemplate_ = false;
        }
        if (root.contains("groups") && array(root["groups"], "groups"))
            for (size_t i = 0; i < root["groups"].size(); ++i)
                group(root["groups"][i], "groups[" + std::to_string(i) + "]");
    }

    // Whether `value` is an object whose keys are all `allowed` and hold every `required`.
    bool keys(const json& value, const std::string& place, const std::set<std::string>& allowed,
              const std::set<std::string>& required) {
        if (!value.is_object()) {
            fail(place, "not an object");
            return false;
        }
        bool good = true;
        for (const auto& [key, unused] : value.items())
            if (!allowed.count(key)) fail(place, "unknown key \"" + key + "\""), good = false;
        for (const std::string& key : required)
            if (!value.contains(key)) fail(place, "no \"" + key + "\""), good = false;
        return good;
    }

    void number(const json& value, const std::string& place) {
        if (!value.is_number()) fail(place, "not a number");
    }
    void string(const json& value, const std::string& place) {
        if (!value.is_string()) fail(place, "not a string");
    }
    bool array(const json& value, const std::string& place) {
        if (!value.is_array()) fail(place, "not an array");
        return value.is_array();
    }
    void numbers(const json& value, size_t count, const std::string& place) {
        if (!value.is_array() || value.size() != count) return fail(place, "not " + std::to_string(count) + " numbers");
        for (const json& element : value) number(element, place);
    }

    void camera(const json& camera) {
        if (!keys(camera, "cameraData", {"position", "up", "heightAngle", "look", "focus", "aperture", "focalLength"},
                  {"position", "up", "heightAngle"}))
            return;
        if (camera.contains("look") == camera.contains("focus")) fail("cameraData", "not exactly one of look and focus");
        for (const char* key : {"position", "up", "look", "focus"})
            if (camera.contains(key)) numbers(camera[key], 3, std::string("cameraData.") + key);
        for (const char* key : {"heightAngle", "aperture", "focalLength"})
            if (camera.contains(key)) number(camera[key], std::string("cameraData.") + key);
    }

    // `definition`: a template's own group, whose name defines it rather than places it.
    void group(const json& group, const std::string& place, bool definition = false) {
        if (!keys(group, place, {"name", "translate", "rotate", "scale", "matrix", "lights", "primitives", "groups"}, {}))
            return;
        if (group.contains("name")) {
            string(group["name"], place + ".name");
            // Inside a template, a group placing another template must come after its definition.
            const std::string name = group["name"].is_string() ? group["name"].get<std::string>() : "";
            if (inTemplate_ && !definition && allTemplates_.count(name) && !defined_.count(name))
                fail(place, "places template \"" + name + "\", which is defined after the template holding it");
        }
        if (group.contains("translate")) numbers(group["translate"], 3, place + ".translate");
        if (group.contains("scale")) numbers(group["scale"], 3, place + ".scale");
        if (group.contains("rotate")) numbers(group["rotate"], 4, place + ".rotate");
        if (group.contains("matrix")) {
            const json& m = group["matrix"];
            if (!m.is_array() || m.size() != 4) fail(place + ".matrix", "not 4 rows");
            else
                for (const json& row : m) numbers(row, 4, place + ".matrix");
        }
        if (group.contains("lights") && array(group["lights"], place + ".lights"))
            for (size_t i = 0; i < group["lights"].size(); ++i)
                light(group["lights"][i], place + ".lights[" + std::to_string(i) + "]");
        if (group.contains("primitives") && array(group["primitives"], place + ".primitives"))
            for (size_t i = 0; i < group["primitives"].size(); ++i)
                primitive(group["primitives"][i], place + ".primitives[" + std::to_string(i) + "]");
        if (group.contains("groups") && array(group["groups"], place + ".groups"))
            for (size_t i = 0; i < group["groups"].size(); ++i)
                this->group(group["groups"][i], place + ".groups[" + std::to_string(i) + "]");
    }

    void light(const json& light, const std::string& place) {
        if (!keys(light, place, {"name", "type", "color", "attenuationCoeff", "direction", "angle", "penumbra"},
                  {"type", "color"}))
            return;
        const std::string type = light["type"].is_string() ? light["type"].get<std::string>() : "";
        std::set<std::string> required;
        if (type == "point") required = {"attenuationCoeff"};
        else if (type == "directional") required = {"direction"};
        else if (type == "spot") required = {"attenuationCoeff", "direction", "angle", "penumbra"};
        else fail(place, "light type \"" + type + "\"");
        for (const std::string& key : required)
            if (!light.contains(key)) fail(place, "a " + type + " light without \"" + key + "\"");
        for (const char* key : {"color", "attenuationCoeff", "direction"})
            if (light.contains(key)) numbers(light[key], 3, place + "." + key);
        for (const char* key : {"angle", "penumbra"})
            if (light.contains(key)) number(light[key], place + "." + key);
    }

    void primitive(const json& primitive, const std::string& place) {
        if (!keys(primitive, place,
                  {"type", "meshFile", "ambient", "diffuse", "specular", "reflective", "transparent", "shininess", "ior",
                   "blend", "textureFile", "textureU", "textureV", "bumpMapFile", "bumpMapU", "bumpMapV"},
                  {"type"}))
            return;
        static const std::set<std::string> kTypes{"cube", "sphere", "cylinder", "cone", "mesh"};
        const std::string type = primitive["type"].is_string() ? primitive["type"].get<std::string>() : "";
        if (!kTypes.count(type)) fail(place, "primitive type \"" + type + "\"");
        if (type == "mesh" && !primitive.contains("meshFile")) fail(place, "a mesh without \"meshFile\"");
        for (const char* key : {"ambient", "diffuse", "specular", "reflective", "transparent"})
            if (primitive.contains(key)) numbers(primitive[key], 3, place + "." + key);
        for (const char* key : {"shininess", "ior", "blend", "textureU", "textureV", "bumpMapU", "bumpMapV"})
            if (primitive.contains(key)) number(primitive[key], place + "." + key);
        for (const char* key : {"meshFile", "textureFile", "bumpMapFile"})
            if (primitive.contains(key)) string(primitive[key], place + "." + key);
    }

    std::vector<std::string> breaches_;
    std::set<std::string> allTemplates_;  // every template's name
    std::set<std::string> defined_;       // the templates before the one being walked
    bool inTemplate_ = false;
};

}  // namespace ray::test
