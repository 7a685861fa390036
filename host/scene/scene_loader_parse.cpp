// Pass 1 of the scene loader (scene_loader.cpp): the XML into the parsed scene graph,
// every rule that rejects a file checked with the line of the offending element.
#include "scene/scene_loader_passes.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "scene/parameter_rules.h"
#include "scene/value_text.h"

namespace ray::loader {
namespace {

// ---------------------------------------------------------------------------------------
// Small helpers for names and text

std::string tag(XmlElement element) { return std::string("<") + element.name() + ">"; }

bool isBlank(const char* text) {
    for (; *text; ++text)
        if (!std::isspace(static_cast<unsigned char>(*text))) return false;
    return true;
}

// "C:\\Users\\...": FileSearch only tries the trailing parts of these.
bool isWindowsDrivePath(const std::string& path) {
    return path.size() >= 2 && std::isalpha(static_cast<unsigned char>(path[0])) && path[1] == ':';
}

// ---------------------------------------------------------------------------------------
// Attributes, read by position (SPEC §1: their names do not matter)

class Values {
public:
    Values(XmlElement element, const Diagnostics& diagnostics) : element_(element), diagnostics_(diagnostics) {}

    size_t count() const { return element_.attributeCount(); }
    int line() const { return element_.line(); }

    // Checks the number of attributes: fewer than `required` is an error, more than
    // `required + optional` a warning. `usage` names them, as in "x y z".
    void expect(size_t required, size_t optional, const char* usage) const {
        if (count() < required)
            diagnostics_.error(line(),
                               tag(element_) + " needs " + std::to_string(required) + " value" +
                                   (required == 1 ? "" : "s") + " (" + usage + ") but has " +
                                   std::to_string(count()),
                               std::string("write it as ") + example(usage));
        for (size_t i = required + optional; i < count(); ++i)
            diagnostics_.warning(line(), "unknown attribute '" + std::string(element_.attributeName(i)) +
                                             "' of " + tag(element_) + " (it takes " + usage +
                                             "); it is ignored");
    }

    const char* text(size_t i) const { return element_.attributeValue(i); }

    double number(size_t i) const {
        const char* text = element_.attributeValue(i);
        const NumberReading read = readNumber(text);
        // The common case first, without building any message.
        if (read.kind == NumberReading::Kind::Number) return read.value;
        std::string what = "attribute '" + std::string(element_.attributeName(i)) + "' of " + tag(element_);
        switch (read.kind) {
            case NumberReading::Kind::Number: break;
            case NumberReading::Kind::Blank: diagnostics_.warning(line(), "empty " + what + " reads as 0"); break;
            case NumberReading::Kind::StrayEquals:
                // A typo whose intent is plain; the number after it is read, and we say so.
                diagnostics_.warning(line(), "'" + std::string(text) + "' has a stray '=' (" + what +
                                                 "); it reads as " + std::string(text + 1));
                break;
            case NumberReading::Kind::NotANumber:
                diagnostics_.error(line(), "'" + std::string(text) + "' is not a number (" + what + ")",
                                   "write a decimal number such as 1.5");
            case NumberReading::Kind::NotFinite:
                diagnostics_.error(line(), "'" + std::string(text) + "' is not a finite number (" + what + ")",
                                   "write a finite decimal number");
        }
        return read.value;
    }

    double numberOr(size_t i, double fallback) const { return i < count() ? number(i) : fallback; }

    Vec3 vec3() const { return {number(0), number(1), number(2)}; }

private:
    std::string example(const char* usage) const {
        std::istringstream names(usage);
        std::string result = "<" + std::string(element_.name()), name;
        while (names >> name)
            if (name.front() != '[') result += " " + name + "=\"...\"";
        return result + "/>";
    }

    XmlElement element_;
    const Diagnostics& diagnostics_;
};

// ---------------------------------------------------------------------------------------
// Pass 1: parsing

class SceneParser {
public:
    SceneParser(const Diagnostics& diagnostics, const FileSearch& search, SceneDocument& document,
                bool keepTransforms)
        : diagnostics_(diagnostics), search_(search), document_(document), keepTransforms_(keepTransforms) {}

    void parseDocument(XmlElement root) {
        document_.scenefileLine = root.line();
        if (!sameName(root.name(), "scenefile"))
            diagnostics_.error(root.line(), "the root element is " + tag(root) + ", not <scenefile>",
                               "give a CS123 scene file");
        expectNoAttributes(root);
        for (XmlElement child = root.firstChild(); child; child = child.nextSibling()) {
            if (sameName(child.name(), "globaldata"))
                parseGlobals(child);
            else if (sameName(child.name(), "cameradata"))
                parseCamera(child);
            else if (sameName(child.name(), "lightdata"))
                parseLight(child);
            else if (sameName(child.name(), "object"))
                parseTopLevelTree(child);
            else
                warnUnknown(child, root);
        }
    }

private:
    // Containers (<globaldata>, <transblock> …) take no attributes: any is unknown.
    void expectNoAttributes(XmlElement element) const {
        Values(element, diagnostics_).expect(0, 0, "no attributes");
    }

    void warnUnknown(XmlElement element, XmlElement parent) const {
        diagnostics_.warning(element.line(),
                             "unknown element " + tag(element) + " in " + tag(parent) + "; it is ignored");
    }

    // <globaldata>
    void parseGlobals(XmlElement element) {
        expectNoAttributes(element);
        GlobalCoefficients& g = document_.globals;
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            const char* name = child.name();
            double* target = sameName(name, "ambientcoeff")       ? &g.ka
                             : sameName(name, "diffusecoeff")     ? &g.kd
                             : sameName(name, "specularcoeff")    ? &g.ks
                             : sameName(name, "transparentcoeff") ? &g.kt
                                                                  : nullptr;
            if (target)
                *target = single(child);
            else
                warnUnknown(child, element);
        }
    }

    // <cameradata>: look is a direction, focus a point; one or the other.
    void parseCamera(XmlElement element) {
        expectNoAttributes(element);
        Camera& camera = document_.camera;
        std::optional<Vec3> focus;
        int lookLine = 0, focusLine = 0;
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            const char* name = child.name();
            if (sameName(name, "pos")) {
                camera.position = triple(child);
            } else if (sameName(name, "look")) {
                camera.look = triple(child);
                lookLine = child.line();
            } else if (sameName(name, "focus")) {
                focus = triple(child);
                focusLine = child.line();
            } else if (sameName(name, "up")) {
                camera.up = triple(child);
            } else if (sameName(name, "heightangle")) {
                camera.heightAngleDegrees = obeying(child, rules::kHeightAngle, single(child));
            } else if (sameName(name, "aspectratio")) {
                single(child);  // validated, then ignored: the image's width/height rule
            } else if (sameName(name, "aperture")) {
                camera.aperture = single(child);
            } else if (sameName(name, "focallength")) {
                camera.focalLength = single(child);
            } else {
                warnUnknown(child, element);
            }
        }
        if (lookLine && focusLine)
            diagnostics_.error(std::max(lookLine, focusLine), "the camera has both <look> and <focus>",
                               "keep one: look is a direction, focus is a point to look at");
        if (focus) camera.look = *focus - camera.position;
        checkCameraAxes(element, camera);
    }

    void checkCameraAxes(XmlElement element, const Camera& camera) const {
        if (std::optional<RuleBroken> broken =
                brokenCameraAxes(camera, "<look>, or a <focus> point away from <pos>", "<up>"))
            diagnostics_.error(element.line(), broken->problem, broken->remedy);
    }

    // <lightdata>: every field is read whatever the type; the renderer uses what applies.
    void parseLight(XmlElement element) {
        expectNoAttributes(element);
        Light light;
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            const char* name = child.name();
            if (sameName(name, "id")) {
                single(child);  // validated; lights are identified by their order
            } else if (sameName(name, "type")) {
                light.type = lightType(child);
            } else if (sameName(name, "color")) {
                light.color = obeying(child, rules::kColorChannel, color(child));
            } else if (sameName(name, "function")) {
                light.attenuation = obeying(child, rules::kAttenuation, triple(child));
            } else if (sameName(name, "position")) {
                light.position = triple(child);
            } else if (sameName(name, "direction")) {
                light.direction = triple(child);
            } else if (sameName(name, "angle")) {
                light.angleDegrees = obeying(child, rules::kSpotAngle, single(child));
            } else if (sameName(name, "penumbra")) {
                light.penumbraDegrees = obeying(child, rules::kPenumbra, single(child));
            } else if (sameName(name, "radius")) {
                light.radius = obeying(child, rules::kSpotRadius, single(child));
            } else if (sameName(name, "width")) {
                light.width = obeying(child, rules::kAreaSide, single(child));
            } else if (sameName(name, "height")) {
                light.height = obeying(child, rules::kAreaSide, single(child));
            } else {
                warnUnknown(child, element);
            }
        }
        document_.lights.push_back(light);
        document_.lightSources.push_back(element.index());
    }

    LightType lightType(XmlElement element) const {
        Values values(element, diagnostics_);
        values.expect(1, 0, "v");
        const char* type = values.text(0);
        if (sameName(type, "point")) return LightType::Point;
        if (sameName(type, "directional")) return LightType::Directional;
        if (sameName(type, "spot")) return LightType::Spot;
        if (sameName(type, "area")) return LightType::Area;
        diagnostics_.error(element.line(), "unknown light type '" + std::string(values.text(0)) + "'",
                           "use point, directional, spot or area");
    }

    // A top-level <object type="tree" name="N">.
    void parseTopLevelTree(XmlElement element) {
        Values values(element, diagnostics_);
        if (values.count() == 0 || !sameName(values.text(0), "tree"))
            diagnostics_.error(element.line(), "a top-level <object> must be a tree",
                               "write <object type=\"tree\" name=\"...\"> and put primitives in its transblocks");
        if (values.count() < 2)
            diagnostics_.error(element.line(), "a top-level tree needs a name",
                               "add name=\"root\" for the scene, or another name to use it as a master");
        values.expect(2, 0, "type name");
        std::string name = values.text(1);
        auto [it, added] = document_.trees.try_emplace(name);
        if (!added)
            diagnostics_.error(element.line(),
                               "a second tree named '" + name + "' (the first is on line " +
                                   std::to_string(it->second.line) + ")",
                               "give each top-level tree its own name");
        document_.treeOrder.push_back(name);
        it->second.name = name;
        it->second.line = element.line();
        it->second.tree = parseTree(element);
        it->second.tree.source = element.index();
    }

    // The transblocks of a tree, top-level or inline.
    TreeNode parseTree(XmlElement element) {
        TreeNode tree;
        size_t children = 0;  // a flat scene's root holds 10^5 blocks: no copies as they come
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) ++children;
        tree.blocks.reserve(children);
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            if (sameName(child.name(), "transblock")) {
                tree.blocks.push_back(parseBlock(child));
            } else if (sameName(child.name(), "object")) {
                diagnostics_.warning(child.line(),
                                     "<object> outside a <transblock>; it is placed as if in a transblock "
                                     "without transforms");
                Block block;
                block.id = document_.nextBlockId++;
                block.bare = true;
                block.items.push_back(parseObject(child));
                tree.blocks.push_back(std::move(block));
            } else {
                warnUnknown(child, element);
            }
        }
        return tree;
    }

    // M = T1 · T2 · … · Tn: the last transform listed acts on the objects first.
    Block parseBlock(XmlElement element) {
        expectNoAttributes(element);
        Block block;
        block.id = document_.nextBlockId++;
        block.source = element.index();
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            if (sameName(child.name(), "object")) {
                block.items.push_back(parseObject(child));
                continue;
            }
            if (sameName(child.name(), "motion")) {
                parseMotion(child, block);
                continue;
            }
            std::optional<TransformOp> transform = parseTransform(child);
            if (!transform) {
                warnUnknown(child, element);
                continue;
            }
            if (keepTransforms_) {
                block.transforms.push_back(*transform);
            } else {  // composed as composeBlock does, in the same order
                auto [to, from] = transform->affine();
                block.toParent = block.toParent * to;
                block.fromParent = from * block.fromParent;
            }
        }
        if (keepTransforms_) composeBlock(block);
        return block;
    }

    // <motion x y z/> (our extension, see the header comment): the block's displacement
    // at the end of the shutter, in the parent's frame. A second one in the same block adds
    // to the first, with a warning (it is more likely a slip than a wish).
    void parseMotion(XmlElement element, Block& block) const {
        Vec3 displacement = triple(element);  // three finite numbers, or an error
        if (block.motion != Vec3{})
            diagnostics_.warning(element.line(),
                                 "a second <motion> in one <transblock>; the displacements add up");
        block.motion += displacement;
    }

    // A transform element (TransformOp::affine gives it and its exact inverse); nullopt
    // for other elements.
    std::optional<TransformOp> parseTransform(XmlElement element) const {
        const char* name = element.name();
        if (sameName(name, "translate")) return op(TransformKind::Translate, triple(element));
        if (sameName(name, "rotate")) {
            Values values(element, diagnostics_);
            values.expect(4, 0, "x y z angle");
            Vec3 axis = values.vec3();
            double degrees = values.number(3);
            TransformOp rotation = op(TransformKind::Rotate, axis);
            rotation.v[3] = degrees;
            if (auto why = rotation.whySingular())
                diagnostics_.error(element.line(), *why,
                                   "give the axis to rotate about, such as x=\"0\" y=\"1\" z=\"0\"");
            return rotation;
        }
        if (sameName(name, "scale")) {
            TransformOp scale = op(TransformKind::Scale, triple(element));
            if (auto why = scale.whySingular())
                diagnostics_.error(element.line(), *why, "use a small non-zero factor, or remove the object");
            return scale;
        }
        if (sameName(name, "matrix")) return parseMatrix(element);
        return std::nullopt;
    }

    // <matrix> with four row children (row0…row3) of four values, row-major.
    static TransformOp op(TransformKind kind, const Vec3& xyz) {
        TransformOp result;
        result.kind = kind;
        result.v[0] = xyz.x, result.v[1] = xyz.y, result.v[2] = xyz.z;
        return result;
    }

    TransformOp parseMatrix(XmlElement element) const {
        expectNoAttributes(element);
        std::vector<XmlElement> rows;
        for (XmlElement row = element.firstChild(); row; row = row.nextSibling())
            rows.push_back(row);
        if (rows.size() != 4)
            diagnostics_.error(element.line(),
                               "<matrix> has " + std::to_string(rows.size()) + " rows, not 4",
                               "give four rows <row0 v1= v2= v3= v4=/> … <row3 …/>");
        Affine m;
        double lastRow[4];
        for (int r = 0; r < 4; ++r) {
            Values values(rows[r], diagnostics_);
            values.expect(4, 0, "v1 v2 v3 v4");
            for (int c = 0; c < 4; ++c) (r < 3 ? m.m[r][c] : lastRow[c]) = values.number(c);
        }
        if (lastRow[0] != 0 || lastRow[1] != 0 || lastRow[2] != 0 || lastRow[3] != 1)
            diagnostics_.error(rows[3].line(), "the matrix's last row is not 0 0 0 1",
                               "give an affine transform (translation in the last column)");
        TransformOp matrix = TransformOp::matrix(m);
        if (auto why = matrix.whySingular()) diagnostics_.error(element.line(), *why, "give an invertible matrix");
        return matrix;
    }

    // <object type="primitive|tree|master" ...> inside a transblock.
    SceneItem parseObject(XmlElement element) {
        Values values(element, diagnostics_);
        if (values.count() == 0)
            diagnostics_.error(element.line(), "<object> has no type",
                               "write type=\"primitive\", \"tree\" or \"master\"");
        const char* type = values.text(0);
        if (sameName(type, "primitive")) return parsePrimitive(element, values);
        if (sameName(type, "tree")) {
            values.expect(1, 1, "type [name]");
            TreeNode tree = parseTree(element);
            tree.source = element.index();
            return Box<TreeNode>(std::move(tree));
        }
        if (sameName(type, "csg")) return parseCsg(element, values);
        if (sameName(type, "master")) {
            if (values.count() < 2)
                diagnostics_.error(element.line(), "a master object needs the name of the tree it places",
                                   "write <object type=\"master\" name=\"...\"/>");
            values.expect(2, 0, "type name");
            return MasterReference{values.text(1), element.line(), nullptr, element.index()};
        }
        diagnostics_.error(element.line(), "unknown object type '" + std::string(values.text(0)) + "'",
                           "use primitive, tree, master or csg");
    }

    // <object type="csg" operation="union|intersection|difference">: every child
    // <transblock> (or bare <object>) is one operand.
    Box<CsgNode> parseCsg(XmlElement element, const Values& values) {
        const char* usage = "write <object type=\"csg\" operation=\"union\"> (or intersection, difference)";
        if (values.count() < 2)
            diagnostics_.error(element.line(), "a csg object needs an operation", usage);
        values.expect(2, 0, "type operation");
        auto node = std::make_unique<CsgNode>();
        node->line = element.line();
        node->source = element.index();
        const char* operation = values.text(1);
        if (sameName(operation, "union")) node->operation = CsgStepKind::Union;
        else if (sameName(operation, "intersection")) node->operation = CsgStepKind::Intersection;
        else if (sameName(operation, "difference")) node->operation = CsgStepKind::Difference;
        else diagnostics_.error(element.line(), "unknown csg operation '" + std::string(values.text(1)) + "'", usage);
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            TreeNode operand;
            if (sameName(child.name(), "transblock")) {
                operand.blocks.push_back(parseBlock(child));
            } else if (sameName(child.name(), "object")) {
                Block& block = operand.blocks.emplace_back();
                block.id = document_.nextBlockId++;
                block.bare = true;
                block.items.push_back(parseObject(child));
            } else {
                warnUnknown(child, element);
                continue;
            }
            node->operands.push_back(std::move(operand));
        }
        if (node->operands.size() < 2)
            diagnostics_.error(element.line(),
                               "a csg object needs two or more operands but has " +
                                   std::to_string(node->operands.size()),
                               "put each operand in a <transblock> of its own inside the csg object");
        return Box<CsgNode>(std::move(node));
    }

    PrimitiveNode parsePrimitive(XmlElement element, const Values& values) {
        ++document_.primitiveElements;
        if (values.count() < 2)
            diagnostics_.error(element.line(), "a primitive needs a name",
                               "write name=\"cube\" (or sphere, cylinder, cone, torus, mesh)");
        PrimitiveNode node;
        node.line = element.line();
        node.id = document_.nextObjectId++;
        node.source = element.index();
        node.type = primitiveType(element, values.text(1));
        if (node.type == PrimitiveType::Mesh) {
            if (values.count() < 3)
                diagnostics_.error(element.line(), "a mesh primitive needs its OBJ file",
                                   "add meshfile=\"path/to/file.obj\" after the name");
            values.expect(3, 0, "type name meshfile");
            node.filesToSet().meshFile = resolveMesh(element, values.text(2));
            node.files->meshWritten = values.text(2);
        } else {
            values.expect(2, 0, "type name");
        }
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling())
            parseMaterialElement(child, element, node);
        return node;
    }

    PrimitiveType primitiveType(XmlElement element, const std::string& name) const {
        static const std::pair<const char*, PrimitiveType> kNames[] = {
            {"cube", PrimitiveType::Cube},   {"sphere", PrimitiveType::Sphere}, {"cylinder", PrimitiveType::Cylinder},
            {"cone", PrimitiveType::Cone},   {"torus", PrimitiveType::Torus},   {"mesh", PrimitiveType::Mesh},
        };
        for (const auto& [known, type] : kNames)
            if (sameName(name.c_str(), known)) return type;
        diagnostics_.error(element.line(), "unknown primitive '" + name + "'",
                           "use cube, sphere, cylinder, cone, torus or mesh");
    }

    fs::path resolveMesh(XmlElement element, const std::string& reference) const {
        std::vector<fs::path> tried;
        if (std::optional<fs::path> found = search_.resolve(reference, &tried)) return *found;
        diagnostics_.error(element.line(),
                           "mesh file '" + reference + "' not found (" + whereLooked(reference, tried, search_) + ")",
                           "put the OBJ file there, or name its folder with a search path");
    }

    // The material children of a primitive: each sets one field.
    void parseMaterialElement(XmlElement element, XmlElement primitive, PrimitiveNode& node) {
        Material& m = node.material;
        const char* name = element.name();
        if (sameName(name, "diffuse")) m.diffuse = materialColor(element);
        else if (sameName(name, "ambient")) m.ambient = materialColor(element);
        else if (sameName(name, "specular")) m.specular = materialColor(element);
        else if (sameName(name, "reflective")) m.reflective = materialColor(element);
        else if (sameName(name, "transparent")) m.transparent = materialColor(element);
        else if (sameName(name, "emissive")) m.emissive = materialColor(element);
        else if (sameName(name, "shininess")) m.shininess = obeying(element, rules::kShininess, single(element));
        else if (sameName(name, "ior")) m.ior = obeying(element, rules::kIor, single(element));
        else if (sameName(name, "blend")) m.blend = obeying(element, rules::kBlend, single(element));
        else if (sameName(name, "texture")) imageReference(element, m.texture, "texture", node.filesToSet().texture, node.filesToSet().missingTexture);
        else if (sameName(name, "bumpmap")) imageReference(element, m.bumpMap, "bump map", node.filesToSet().bumpMap, node.filesToSet().missingBumpMap);
        else warnUnknown(element, primitive);
    }

    // <texture file u v> or <bumpmap file u v>: sets the repeats and resolves the file.
    // A file that cannot be found is a warning (once per file name; scenes repeat one
    // texture hundreds of times): the surface keeps its material colors.
    // The reference goes to `found`, or, as written, to `missing` when it is not found.
    void imageReference(XmlElement element, TextureMap& map, const char* what, std::optional<ImageReference>& found,
                        std::string& missing) {
        found.reset();
        missing.clear();
        std::string reference;
        found = resolveImage(element, map, what, reference);
        if (!found) missing = reference;
    }

    std::optional<ImageReference> resolveImage(XmlElement element, TextureMap& map, const char* what,
                                               std::string& reference) {
        Values values(element, diagnostics_);
        values.expect(1, 2, "file [u] [v]");
        map.repeatU = values.numberOr(1, 1.0);
        map.repeatV = values.numberOr(2, 1.0);
        reference = values.text(0);
        if (isBlank(reference.c_str())) {
            diagnostics_.warning(element.line(), std::string(what) + " without a file name; it is ignored");
            return std::nullopt;
        }
        auto [known, isNew] = resolvedImages_.try_emplace(reference);
        if (!isNew) {
            if (!known->second) return std::nullopt;
            return ImageReference{*known->second, element.line(), reference};
        }
        std::vector<fs::path> tried;
        known->second = search_.resolve(reference, &tried);
        if (known->second) return ImageReference{*known->second, element.line(), reference};
        if (auto special = firstNonRegular(tried)) {
            diagnostics_.warning(element.line(), std::string(what) + " file " + special->string() +
                                                           " is not a regular file (a FIFO, device or folder: reading "
                                                           "it could block or never end); it is not read, and the "
                                                           "surface keeps its material colors");
            return std::nullopt;
        }
        diagnostics_.warning(element.line(), std::string(what) + " file '" + reference + "' not found (" +
                                                       whereLooked(reference, tried, search_) +
                                                       "); the surface keeps its material colors");
        return std::nullopt;
    }

    double single(XmlElement element) const {
        Values values(element, diagnostics_);
        values.expect(1, 0, "v");
        return values.number(0);
    }

    Vec3 triple(XmlElement element) const {
        Values values(element, diagnostics_);
        values.expect(3, 0, "x y z");
        return values.vec3();
    }

    // r g b, and an alpha the format allows and the renderer does not use.
    Vec3 color(XmlElement element) const {
        Values values(element, diagnostics_);
        values.expect(3, 1, "r g b [a]");
        if (values.count() > 3) values.number(3);  // validated, then ignored
        return values.vec3();
    }

    Vec3 materialColor(XmlElement element) const { return obeying(element, rules::kColorChannel, color(element)); }

    // The value, once it keeps its rule (parameter_rules.h, shared with the public API);
    // an error at the element's line otherwise.
    template <class Value>
    Value obeying(XmlElement element, const NumberRule& rule, Value value) const {
        if (std::optional<RuleBroken> broken = brokenRule(element.name(), value, rule))
            diagnostics_.error(element.line(), broken->problem, broken->remedy);
        return value;
    }

    const Diagnostics& diagnostics_;
    const FileSearch& search_;
    SceneDocument& document_;
    const bool keepTransforms_;
    std::map<std::string, std::optional<fs::path>> resolvedImages_;  // by reference as written
};

}  // namespace

std::optional<fs::path> firstNonRegular(const std::vector<fs::path>& tried) {
    for (const fs::path& path : tried) {
        std::error_code ec;
        const fs::file_status status = fs::status(path, ec);
        if (!ec && fs::exists(status) && !fs::is_regular_file(status)) return path;
    }
    return std::nullopt;
}

// Listing every candidate would run to dozens of paths: the first, then the roots.
std::string whereLooked(const std::string& reference, const std::vector<fs::path>& tried, const FileSearch& search) {
    std::vector<std::string> roots;
    for (const fs::path& root : search.searchRoots()) roots.push_back(root.string());
    std::string text = "looked ";
    if (!tried.empty() && !isWindowsDrivePath(reference)) text += "at " + tried.front().string() + ", then ";
    return text + "for the path and each of its trailing parts under " + joined(roots, ", ");
}

void parseSceneDocument(XmlElement root, const Diagnostics& diagnostics, const FileSearch& search,
                        SceneDocument& document, bool keepTransforms) {
    SceneParser(diagnostics, search, document, keepTransforms).parseDocument(root);
}

}  // namespace ray::loader
