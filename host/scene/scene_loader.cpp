// Reading a CS123 scenefile (SPEC §1) into a flattened Scene.
//
// The work is done in three passes:
//  1. parse: the XML becomes a small tree of blocks, one per <transblock>, each holding its
//     composed transform and inverse (computed once) and its objects: primitives, inline
//     subtrees and master references. Every rule that rejects a file is checked here, with
//     the line of the offending element, and file references are resolved (SPEC §1 search).
//  2. count: the instances each top-level tree flattens to, memoized per tree, which also
//     resolves master names and finds cycles. A scene over LoadOptions::maxPrimitives is
//     refused before a single instance is made (recursiveSpheres10.xml makes ~2.9 million).
//  3. flatten: the root tree is walked with composed transforms. A primitive element gets
//     its Material (and its images, each file loaded once) on first use, and every instance
//     made from that element shares it.
//
// Choices the spec leaves open:
//  - With options.loadImages false a texture file is still resolved (a missing one still
//    warns) and gets its index into Scene::imageFiles, with an empty Image at the same index
//    of Scene::images: renderers treat an empty image as no texture.
//  - A texture or bump map that exists but does not decode warns like a missing one, and
//    its TextureMap::image stays -1.
//  - A singular transform (a zero scale, a zero rotation axis, a singular matrix) is an
//    error at the line of that transform: the primitives under it could not be rendered,
//    and an error says why where silently dropping them would not.
//  - A matrix whose last row is not 0 0 0 1 is an error (only affine transforms exist).
//  - Transforms listed after objects in a transblock still apply to all its objects, as in
//    the course's parser (pdiddy.xml relies on it).
//  - An object directly in a tree, outside any transblock, is taken as if it were in a
//    transblock without transforms, with a warning.
//  - A file without any tree (the course's modeler template empty.xml) is an empty scene,
//    with a warning; a file with trees but none named "root" is an error.
//  - Element names and keywords (object types, primitive names, light types) are matched
//    ignoring case; tree names are matched exactly.
//  - Inline subtrees may carry a name; it is ignored (masters name top-level trees only).
//  - A material's or a light's number outside what SPEC §4's model gives a meaning to (a
//    negative shininess or color, an ior of 0, a blend beyond 1) is an error at its line;
//    the rules are scene/parameter_rules.h, which the public API applies too.
//
// Our extension, motion blur: <motion x="" y="" z=""/> in a <transblock> moves everything
// in that block (primitives, subtrees, masters) by the translation (x, y, z) over the
// shutter, expressed in the block's parent frame (the frame its transforms act in, so
// its place among them does not matter). At shutter time t ∈ [0, 1] the block's contents
// are translated by t·(x, y, z) in that frame; t = 0 is the static scene. Nested motions
// compose: a primitive's world-space motion (PrimitiveInstance::motion) is the sum over
// its enclosing blocks of each block's motion carried to world space by its parent's
// linear transform, which is exactly the composition of the translations. Only
// translation moves (no rotation or scale over time). A second <motion> in one block adds
// to the first, with a warning.
#include "scene/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <variant>

#include "scene/file_search.h"
#include "scene/parameter_rules.h"
#include "scene/xml_tree.h"
#include "core/memory_limits.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

// ---------------------------------------------------------------------------------------
// Messages

// Formats errors and warnings as "<file>:<line>: error: ..." and routes warnings to the
// caller (or stderr); with the strict option a warning is thrown as an error instead.
class Diagnostics {
public:
    Diagnostics(std::string file, const LoadOptions& options) : file_(std::move(file)), options_(options) {}

    // `problem` says what is wrong, `remedy` what to do about it.
    [[noreturn]] void error(int line, const std::string& problem, const std::string& remedy) const {
        throw InputError(where(line) + "error: " + problem + "; " + remedy);
    }

    void warning(int line, const std::string& message) const {
        if (options_.strict)
            throw InputError(where(line) + "error: " + message + " (strict mode turns warnings into errors)");
        std::string text = where(line) + "warning: " + message;
        if (options_.warn)
            options_.warn(text);
        else
            std::cerr << text << std::endl;
    }

private:
    std::string where(int line) const {
        return line > 0 ? file_ + ":" + std::to_string(line) + ": " : file_ + ": ";
    }

    std::string file_;
    const LoadOptions& options_;
};

// ---------------------------------------------------------------------------------------
// Small helpers for names and text

constexpr char asciiLower(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }

// Names and keywords match ignoring case, ASCII only as strcasecmp in the C locale does.
// Inline: a large flat scene compares millions of names, and the calls to strcasecmp were a
// sixth of its parse.
bool sameName(const char* a, const char* b) {
    if (!a || !b) return false;
    for (;; ++a, ++b) {
        const char x = asciiLower(*a);
        if (x != asciiLower(*b)) return false;
        if (x == '\0') return true;
    }
}

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

std::string joined(const std::vector<std::string>& items, const char* separator) {
    std::string result;
    for (const std::string& item : items) result += (result.empty() ? "" : separator) + item;
    return result;
}

// A plain decimal ("-3.65636", "0.1", "20": an optional '-', digits with an optional
// point, nothing else) of at most 19 digits, at most 22 of them after the point, whose
// digits make an integer w <= 2^53, is w / 10^k with both w and 10^k exact doubles: the one
// division, rounded correctly, gives exactly strtod's value (Clinger's fast path). Nullopt
// for anything else. A large flat scene has millions of numbers, and strtod was a tenth of
// its load.
std::optional<double> plainDecimal(const char* text) {
    static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                              1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                              1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* p = text;
    const bool negative = *p == '-';
    if (negative) ++p;
    uint64_t digits = 0;
    int count = 0, afterPoint = -1;  // -1: no point yet
    for (;; ++p) {
        if (*p >= '0' && *p <= '9') {
            if (++count > 19) return std::nullopt;
            digits = digits * 10 + uint64_t(*p - '0');
            if (afterPoint >= 0) ++afterPoint;
        } else if (*p == '.' && afterPoint < 0) {
            afterPoint = 0;
        } else {
            break;
        }
    }
    if (*p != '\0' || count == 0 || digits > (uint64_t(1) << 53) || afterPoint > 22) return std::nullopt;
    const double value = double(digits) / kPowersOfTen[std::max(afterPoint, 0)];
    return negative ? -value : value;
}

// The value `text` holds when it is a whole decimal number (surrounding blanks allowed).
std::optional<double> parseNumber(const char* text) {
    if (std::optional<double> value = plainDecimal(text)) return value;
    char* end = nullptr;
    double value = std::strtod(text, &end);
    if (end == text) return std::nullopt;
    while (std::isspace(static_cast<unsigned char>(*end))) ++end;
    if (*end != '\0') return std::nullopt;
    return value;
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
        // The common case first, without building any message.
        if (std::optional<double> value = parseNumber(text); value && std::isfinite(*value)) return *value;
        std::string what = "attribute '" + std::string(element_.attributeName(i)) + "' of " + tag(element_);
        if (isBlank(text)) {
            diagnostics_.warning(line(), "empty " + what + " reads as 0");
            return 0;
        }
        std::optional<double> value = parseNumber(text);
        if (!value && text[0] == '=' && (value = parseNumber(text + 1)))
            // A stray '=' ("r="=0.1"", as in the course's pikachu_head.xml) is a typo whose
            // intent is plain; read the number after it, and say so.
            diagnostics_.warning(line(), "'" + std::string(text) + "' has a stray '=' (" + what +
                                             "); it reads as " + std::string(text + 1));
        if (!value)
            diagnostics_.error(line(), "'" + std::string(text) + "' is not a number (" + what + ")",
                               "write a decimal number such as 1.5");
        if (!std::isfinite(*value))
            diagnostics_.error(line(), "'" + std::string(text) + "' is not a finite number (" + what + ")",
                               "write a finite decimal number");
        return *value;
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
// The parsed scene graph

// A texture or bump map file, resolved, and the line that names it.
struct ImageReference {
    fs::path file;
    int line = 0;
};

// What few primitives name, kept apart so that the common primitive stays small (a large
// flat scene holds 10^5 of them).
struct PrimitiveFiles {
    std::optional<ImageReference> texture, bumpMap;
    fs::path meshFile;  // resolved; meshes only
};

struct PrimitiveNode {
    PrimitiveType type = PrimitiveType::Cube;
    int line = 0;
    Material material;  // image indices filled in on first use
    std::unique_ptr<PrimitiveFiles> files;  // null when it names none
    // Indices into the Scene, set when the first instance is made.
    int sceneMaterial = -1;
    int sceneMesh = -1;

    PrimitiveFiles& filesToSet() {
        if (!files) files = std::make_unique<PrimitiveFiles>();
        return *files;
    }
};

struct TreeNode;
struct NamedTree;

struct MasterReference {
    std::string name;
    int line = 0;
    NamedTree* target = nullptr;  // set by the count pass
};

struct CsgNode;

using SceneItem = std::variant<PrimitiveNode, std::unique_ptr<TreeNode>, MasterReference, std::unique_ptr<CsgNode>>;

struct Block {
    Affine toParent;    // T1 · T2 · … · Tn
    Affine fromParent;  // its inverse, composed from the exact inverses of each Ti
    Vec3 motion;        // <motion>: the end-of-shutter displacement, in the parent's frame
    std::vector<SceneItem> items;
};

struct TreeNode {
    std::vector<Block> blocks;
};

// <object type="csg" operation="..."> (scene/csg.h): each operand is written as a tree's
// children are, one <transblock> (or one bare <object>) per operand.
struct CsgNode {
    CsgStepKind operation = CsgStepKind::Union;
    int line = 0;
    std::vector<TreeNode> operands;
};

struct NamedTree {
    enum class State { Uncounted, Counting, Counted };
    std::string name;
    int line = 0;
    TreeNode tree;
    State state = State::Uncounted;
    uint64_t instances = 0;
    int levels = 0;  // how deep trees and masters nest inside it (set by the count pass)
};

// ---------------------------------------------------------------------------------------
// Pass 1: parsing

class SceneParser {
public:
    SceneParser(const Diagnostics& diagnostics, const FileSearch& search, Scene& scene)
        : diagnostics_(diagnostics), search_(search), scene_(scene) {}

    void parseDocument(XmlElement root) {
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

    std::map<std::string, NamedTree>& trees() { return trees_; }
    size_t primitiveElements() const { return primitiveElements_; }

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
        GlobalCoefficients& g = scene_.globals;
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
        Camera& camera = scene_.camera;
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
        scene_.lights.push_back(light);
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
        auto [it, added] = trees_.try_emplace(name);
        if (!added)
            diagnostics_.error(element.line(),
                               "a second tree named '" + name + "' (the first is on line " +
                                   std::to_string(it->second.line) + ")",
                               "give each top-level tree its own name");
        it->second.name = name;
        it->second.line = element.line();
        it->second.tree = parseTree(element);
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
        for (XmlElement child = element.firstChild(); child; child = child.nextSibling()) {
            if (sameName(child.name(), "object")) {
                block.items.push_back(parseObject(child));
                continue;
            }
            if (sameName(child.name(), "motion")) {
                parseMotion(child, block);
                continue;
            }
            std::optional<std::pair<Affine, Affine>> transform = parseTransform(child);
            if (!transform) {
                warnUnknown(child, element);
                continue;
            }
            block.toParent = block.toParent * transform->first;
            block.fromParent = transform->second * block.fromParent;
        }
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

    // A transform element and its exact inverse; nullopt for other elements.
    std::optional<std::pair<Affine, Affine>> parseTransform(XmlElement element) const {
        const char* name = element.name();
        if (sameName(name, "translate")) {
            Vec3 t = triple(element);
            return std::pair{Affine::translation(t), Affine::translation(-t)};
        }
        if (sameName(name, "rotate")) {
            Values values(element, diagnostics_);
            values.expect(4, 0, "x y z angle");
            Vec3 axis = values.vec3();
            double degrees = values.number(3);
            if (length(axis) == 0)
                diagnostics_.error(element.line(), "the rotation axis is zero",
                                   "give the axis to rotate about, such as x=\"0\" y=\"1\" z=\"0\"");
            return std::pair{Affine::rotation(axis, degrees), Affine::rotation(axis, -degrees)};
        }
        if (sameName(name, "scale")) {
            Vec3 s = triple(element);
            if (s.x == 0 || s.y == 0 || s.z == 0)
                diagnostics_.error(element.line(), "a zero scale flattens what it holds to nothing",
                                   "use a small non-zero factor, or remove the object");
            return std::pair{Affine::scaling(s), Affine::scaling({1 / s.x, 1 / s.y, 1 / s.z})};
        }
        if (sameName(name, "matrix")) return parseMatrix(element);
        return std::nullopt;
    }

    // <matrix> with four row children (row0…row3) of four values, row-major.
    std::pair<Affine, Affine> parseMatrix(XmlElement element) const {
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
        Affine inverse = m.inverse();
        if (!std::isfinite(inverse.m[0][0]))
            diagnostics_.error(element.line(), "the matrix is singular (it flattens what it holds)",
                               "give an invertible matrix");
        return {m, inverse};
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
            return std::make_unique<TreeNode>(parseTree(element));
        }
        if (sameName(type, "csg")) return parseCsg(element, values);
        if (sameName(type, "master")) {
            if (values.count() < 2)
                diagnostics_.error(element.line(), "a master object needs the name of the tree it places",
                                   "write <object type=\"master\" name=\"...\"/>");
            values.expect(2, 0, "type name");
            return MasterReference{values.text(1), element.line(), nullptr};
        }
        diagnostics_.error(element.line(), "unknown object type '" + std::string(values.text(0)) + "'",
                           "use primitive, tree, master or csg");
    }

    // <object type="csg" operation="union|intersection|difference">: every child
    // <transblock> (or bare <object>) is one operand.
    std::unique_ptr<CsgNode> parseCsg(XmlElement element, const Values& values) {
        const char* usage = "write <object type=\"csg\" operation=\"union\"> (or intersection, difference)";
        if (values.count() < 2)
            diagnostics_.error(element.line(), "a csg object needs an operation", usage);
        values.expect(2, 0, "type operation");
        auto node = std::make_unique<CsgNode>();
        node->line = element.line();
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
                operand.blocks.emplace_back().items.push_back(parseObject(child));
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
        return node;
    }

    PrimitiveNode parsePrimitive(XmlElement element, const Values& values) {
        ++primitiveElements_;
        if (values.count() < 2)
            diagnostics_.error(element.line(), "a primitive needs a name",
                               "write name=\"cube\" (or sphere, cylinder, cone, torus, mesh)");
        PrimitiveNode node;
        node.line = element.line();
        node.type = primitiveType(element, values.text(1));
        if (node.type == PrimitiveType::Mesh) {
            if (values.count() < 3)
                diagnostics_.error(element.line(), "a mesh primitive needs its OBJ file",
                                   "add meshfile=\"path/to/file.obj\" after the name");
            values.expect(3, 0, "type name meshfile");
            node.filesToSet().meshFile = resolveMesh(element, values.text(2));
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
                           "mesh file '" + reference + "' not found (" + whereLooked(reference, tried) + ")",
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
        else if (sameName(name, "texture")) node.filesToSet().texture = imageReference(element, m.texture, "texture");
        else if (sameName(name, "bumpmap")) node.filesToSet().bumpMap = imageReference(element, m.bumpMap, "bump map");
        else warnUnknown(element, primitive);
    }

    // <texture file u v> or <bumpmap file u v>: sets the repeats and resolves the file.
    // A file that cannot be found is a warning (once per file name; scenes repeat one
    // texture hundreds of times): the surface keeps its material colors.
    std::optional<ImageReference> imageReference(XmlElement element, TextureMap& map, const char* what) {
        Values values(element, diagnostics_);
        values.expect(1, 2, "file [u] [v]");
        map.repeatU = values.numberOr(1, 1.0);
        map.repeatV = values.numberOr(2, 1.0);
        std::string reference = values.text(0);
        if (isBlank(reference.c_str())) {
            diagnostics_.warning(element.line(), std::string(what) + " without a file name; it is ignored");
            return std::nullopt;
        }
        auto [known, isNew] = resolvedImages_.try_emplace(reference);
        if (!isNew) {
            if (!known->second) return std::nullopt;
            return ImageReference{*known->second, element.line()};
        }
        std::vector<fs::path> tried;
        known->second = search_.resolve(reference, &tried);
        if (known->second) return ImageReference{*known->second, element.line()};
        if (auto special = firstNonRegular(tried)) {
            diagnostics_.warning(element.line(), std::string(what) + " file " + special->string() +
                                                           " is not a regular file (a FIFO, device or folder: reading "
                                                           "it could block or never end); it is not read, and the "
                                                           "surface keeps its material colors");
            return std::nullopt;
        }
        diagnostics_.warning(element.line(), std::string(what) + " file '" + reference + "' not found (" +
                                                       whereLooked(reference, tried) +
                                                       "); the surface keeps its material colors");
        return std::nullopt;
    }

    // The search takes only regular files; one it passed over that exists (a FIFO,
    // /dev/zero) deserves its own message rather than "not found".
    static std::optional<fs::path> firstNonRegular(const std::vector<fs::path>& tried) {
        for (const fs::path& path : tried) {
            std::error_code ec;
            const fs::file_status status = fs::status(path, ec);
            if (!ec && fs::exists(status) && !fs::is_regular_file(status)) return path;
        }
        return std::nullopt;
    }

    // Says where a search looked: the path as given, then the roots its trailing parts
    // were tried under (listing every candidate would run to dozens of paths).
    std::string whereLooked(const std::string& reference, const std::vector<fs::path>& tried) const {
        std::vector<std::string> roots;
        for (const fs::path& root : search_.searchRoots()) roots.push_back(root.string());
        std::string text = "looked ";
        if (!tried.empty() && !isWindowsDrivePath(reference)) text += "at " + tried.front().string() + ", then ";
        return text + "for the path and each of its trailing parts under " + joined(roots, ", ");
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
    Scene& scene_;
    std::map<std::string, NamedTree> trees_;
    std::map<std::string, std::optional<fs::path>> resolvedImages_;  // by reference as written
    size_t primitiveElements_ = 0;
};

// ---------------------------------------------------------------------------------------
// Pass 2: counting instances, resolving masters, finding cycles

uint64_t saturatingAdd(uint64_t a, uint64_t b) {
    return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max() : a + b;
}

class InstanceCounter {
public:
    InstanceCounter(const Diagnostics& diagnostics, std::map<std::string, NamedTree>& trees)
        : diagnostics_(diagnostics), trees_(trees) {}

    // Counts every top-level tree, so that a bad master is reported even in a tree the
    // scene does not use.
    void countAll() {
        for (auto& [name, tree] : trees_) count(tree, tree.line);
    }

    uint64_t count(NamedTree& tree, int referenceLine) {
        if (tree.state == NamedTree::State::Counted) {
            noteLevel(depth_ + tree.levels, referenceLine);  // a tree counted before, reached deeper
            return tree.instances;
        }
        if (tree.state == NamedTree::State::Counting) reportCycle(tree, referenceLine);
        tree.state = NamedTree::State::Counting;
        path_.push_back(&tree);
        const int entryDepth = depth_, deepestOutside = deepest_;
        deepest_ = depth_;
        tree.instances = count(tree.tree, referenceLine);
        tree.levels = deepest_ - entryDepth;
        deepest_ = std::max(deepest_, deepestOutside);
        path_.pop_back();
        tree.state = NamedTree::State::Counted;
        return tree.instances;
    }

private:
    uint64_t count(TreeNode& node, int line) {
        noteLevel(++depth_, line);
        uint64_t total = 0;
        for (Block& block : node.blocks)
            for (SceneItem& item : block.items) total = saturatingAdd(total, count(item, line));
        --depth_;
        return total;
    }

    void noteLevel(int level, int line) {
        deepest_ = std::max(deepest_, level);
        if (level > kMaxNestingLevels)
            diagnostics_.error(line, "trees and masters nest more than " + std::to_string(kMaxNestingLevels) +
                                         " levels deep",
                               "flatten the hierarchy (fewer levels of masters or nested trees)");
    }

    uint64_t count(SceneItem& item, int line) {
        if (std::holds_alternative<PrimitiveNode>(item)) return 1;
        if (auto* subtree = std::get_if<std::unique_ptr<TreeNode>>(&item)) return count(**subtree, line);
        if (auto* csg = std::get_if<std::unique_ptr<CsgNode>>(&item)) {
            uint64_t total = 0;
            for (TreeNode& operand : (*csg)->operands) total = saturatingAdd(total, count(operand, line));
            return total;
        }
        MasterReference& master = std::get<MasterReference>(item);
        auto it = trees_.find(master.name);
        if (it == trees_.end())
            diagnostics_.error(master.line, "no tree named '" + master.name + "' for this master (trees: " +
                                                treeNames() + ")",
                               "define <object type=\"tree\" name=\"" + master.name +
                                   "\"> at the top level, or fix the name");
        master.target = &it->second;
        return count(it->second, master.line);
    }

    [[noreturn]] void reportCycle(const NamedTree& tree, int line) const {
        std::vector<std::string> cycle;
        bool inCycle = false;
        for (const NamedTree* step : path_) {
            inCycle = inCycle || step == &tree;
            if (inCycle) cycle.push_back(step->name);
        }
        cycle.push_back(tree.name);
        diagnostics_.error(line, "cyclic master reference: " + joined(cycle, " -> "),
                           "a tree cannot contain itself; break the cycle");
    }

    std::string treeNames() const {
        std::vector<std::string> names;
        for (const auto& [name, tree] : trees_) names.push_back(name);
        return joined(names, ", ");
    }

    const Diagnostics& diagnostics_;
    std::map<std::string, NamedTree>& trees_;
    std::vector<const NamedTree*> path_;  // the trees being counted, outermost first
    int depth_ = 0;                        // tree levels entered on the current path
    int deepest_ = 0;                      // the deepest level reached in the tree being counted
};

// ---------------------------------------------------------------------------------------
// Pass 3: flattening

class Flattener {
public:
    Flattener(const Diagnostics& diagnostics, const LoadOptions& options, Scene& scene)
        : diagnostics_(diagnostics), options_(options), scene_(scene) {}

    // worldMotion: the enclosing blocks' end-of-shutter displacement, in world space. A
    // block's own <motion> is in its parent's frame (toWorld), so it adds
    // toWorld's linear part applied to it: translations compose exactly that way.
    void flatten(TreeNode& node, const Affine& toWorld, const Affine& toObject, const Vec3& worldMotion = {}) {
        for (Block& block : node.blocks) {
            Affine blockToWorld = toWorld * block.toParent;
            Affine blockToObject = block.fromParent * toObject;
            Vec3 blockMotion = worldMotion + toWorld.transformVector(block.motion);
            for (SceneItem& item : block.items) {
                if (auto* primitive = std::get_if<PrimitiveNode>(&item))
                    addInstance(*primitive, blockToWorld, blockToObject, blockMotion);
                else if (auto* subtree = std::get_if<std::unique_ptr<TreeNode>>(&item))
                    flatten(**subtree, blockToWorld, blockToObject, blockMotion);
                else if (auto* csg = std::get_if<std::unique_ptr<CsgNode>>(&item))
                    flattenCsg(**csg, blockToWorld, blockToObject, blockMotion);
                else
                    flatten(std::get<MasterReference>(item).target->tree, blockToWorld, blockToObject, blockMotion);
            }
        }
    }

private:
    // A csg object being flattened: its program grows as operands are met; nested csg
    // objects write their sub-programs into the outermost one's.
    struct CsgBuild {
        CsgObject object;
        int line = 0;
        Vec3 motion;          // the object's own; an operand may not move otherwise
        int valuesPushed = 0;  // solids pushed for the operand being flattened
    };

    void flattenCsg(CsgNode& node, const Affine& toWorld, const Affine& toObject, const Vec3& motion) {
        const bool outermost = csg_ == nullptr;
        CsgBuild build;
        if (outermost) {
            build.line = node.line;
            build.motion = motion;
            csg_ = &build;
        }
        const int outerValues = csg_->valuesPushed;
        for (size_t k = 0; k < node.operands.size(); ++k) {
            csg_->valuesPushed = 0;
            flatten(node.operands[k], toWorld, toObject, motion);
            if (csg_->valuesPushed == 0)
                diagnostics_.error(node.line, "operand " + std::to_string(k + 1) + " of this csg object is empty",
                                   "give every operand at least one primitive");
            if (k > 0) csg_->object.program.push_back({node.operation, -1});
        }
        csg_->valuesPushed = outerValues;
        if (!outermost) {
            notePushedSolid();  // the nested object is one solid of the enclosing operand
            return;
        }
        csg_ = nullptr;
        addCsgInstance(build);
    }

    // A solid pushed for the current operand: the second and later ones are unioned in.
    void notePushedSolid() {
        if (++csg_->valuesPushed > 1) csg_->object.program.push_back({CsgStepKind::Union, -1});
    }

    void addCsgOperand(PrimitiveNode& node, const Affine& toWorld, const Affine& toObject, const Vec3& motion) {
        if (node.type == PrimitiveType::Torus || node.type == PrimitiveType::Mesh)
            diagnostics_.error(node.line, std::string("a ") + primitiveTypeName(node.type) +
                                              " cannot be an operand of a csg object (line " +
                                              std::to_string(csg_->line) + ")",
                               "use cubes, spheres, cylinders and cones (convex solids) as csg operands");
        if (motion != csg_->motion)
            diagnostics_.error(node.line, "a <motion> inside a csg object (line " + std::to_string(csg_->line) + ")",
                               "move the whole csg object: put the <motion> in a transblock around it");
        if (int(scene_.csgOperands.size()) >= std::numeric_limits<int>::max() / 2)
            diagnostics_.error(node.line, "too many csg operands", "use fewer csg objects");
        csg_->object.program.push_back({CsgStepKind::Operand, int(scene_.csgOperands.size())});
        scene_.csgOperands.push_back(makeInstance(node, toWorld, toObject, motion));
        notePushedSolid();
    }

    void addCsgInstance(CsgBuild& build) {
        const CsgObject& object = build.object;
        int operands = int(std::count_if(object.program.begin(), object.program.end(),
                                         [](const CsgStep& s) { return s.kind == CsgStepKind::Operand; }));
        if (operands > kCsgMaxOperands)
            diagnostics_.error(build.line, "this csg object holds " + std::to_string(operands) +
                                               " primitives; at most " + std::to_string(kCsgMaxOperands) +
                                               " are allowed",
                               "split it into several csg objects");
        if (csgStackDepth(object) > kCsgMaxStack)
            diagnostics_.error(build.line, "csg objects nest too deeply here (an evaluation stack of " +
                                               std::to_string(csgStackDepth(object)) + ", at most " +
                                               std::to_string(kCsgMaxStack) + ")",
                               "list nested csg objects first among their operands, or nest fewer levels");
        std::vector<Vec3> lo, hi;
        for (const CsgStep& step : object.program) {
            if (step.kind != CsgStepKind::Operand) continue;
            if (lo.size() <= size_t(step.operand)) {
                lo.resize(size_t(step.operand) + 1);
                hi.resize(size_t(step.operand) + 1);
            }
            worldBox(scene_.csgOperands[size_t(step.operand)], lo[size_t(step.operand)], hi[size_t(step.operand)]);
        }
        PrimitiveInstance& instance = scene_.primitives.emplace_back();
        instance.type = PrimitiveType::Csg;
        instance.motion = build.motion;
        instance.material = scene_.csgOperands[size_t(object.program.front().operand)].material;
        instance.csg = int(scene_.csgObjects.size());
        csgBounds(object, lo, hi, instance.objectLo, instance.objectHi);
        scene_.csgObjects.push_back(std::move(build.object));
    }

    // The world box of an instance at rest (its object box's eight corners carried over).
    static void worldBox(const PrimitiveInstance& instance, Vec3& lo, Vec3& hi) {
        lo = {INFINITY, INFINITY, INFINITY};
        hi = -1 * lo;
        for (int corner = 0; corner < 8; ++corner) {
            Vec3 p{corner & 1 ? instance.objectHi.x : instance.objectLo.x,
                   corner & 2 ? instance.objectHi.y : instance.objectLo.y,
                   corner & 4 ? instance.objectHi.z : instance.objectLo.z};
            Vec3 world = instance.objectToWorld.transformPoint(p);
            lo = componentMin(lo, world);
            hi = componentMax(hi, world);
        }
    }

    void addInstance(PrimitiveNode& node, const Affine& toWorld, const Affine& toObject, const Vec3& motion) {
        if (csg_) {
            addCsgOperand(node, toWorld, toObject, motion);
            return;
        }
        scene_.primitives.push_back(makeInstance(node, toWorld, toObject, motion));
    }

    PrimitiveInstance makeInstance(PrimitiveNode& node, const Affine& toWorld, const Affine& toObject,
                                   const Vec3& motion) {
        PrimitiveInstance instance;
        instance.objectToWorld = toWorld;
        instance.worldToObject = toObject;
        instance.motion = motion;
        instance.type = node.type;
        instance.material = materialOf(node);
        instance.mesh = meshOf(node);
        instance.sourceLine = node.line;
        fitObjectBox(instance, scene_.meshes);
        return instance;
    }

    // One Material per primitive element, made on its first instance.
    int materialOf(PrimitiveNode& node) {
        if (node.sceneMaterial >= 0) return node.sceneMaterial;
        Material material = node.material;
        if (node.files && node.files->texture) material.texture.image = imageOf(*node.files->texture);
        if (node.files && node.files->bumpMap) material.bumpMap.image = imageOf(*node.files->bumpMap);
        node.sceneMaterial = int(scene_.materials.size());
        scene_.materials.push_back(material);
        return node.sceneMaterial;
    }

    int meshOf(PrimitiveNode& node) {
        if (node.type != PrimitiveType::Mesh || node.sceneMesh >= 0) return node.sceneMesh;
        node.sceneMesh = indexOf(node.files->meshFile, meshIndex_, [&](const fs::path& file) {
            scene_.meshFiles.push_back(file);
            scene_.meshes.push_back(loadObjMesh(file));  // an unreadable file is an InputError
            return int(scene_.meshFiles.size()) - 1;
        });
        return node.sceneMesh;
    }

    // Each file is read once; one that does not decode is remembered as -1 (no texture).
    int imageOf(const ImageReference& reference) {
        return indexOf(reference.file, imageIndex_, [&](const fs::path& file) {
            Image image;
            if (options_.loadImages) {
                try {
                    image = readImage(file);
                } catch (const std::exception& e) {
                    diagnostics_.warning(reference.line, "cannot read image " + file.string() + " (" + e.what() +
                                                             "); the surface keeps its material colors");
                    return -1;
                }
            }
            scene_.images.push_back(std::move(image));
            scene_.imageFiles.push_back(file);
            return int(scene_.images.size()) - 1;
        });
    }

    // Looks `file` up by its canonical path (so two spellings of one file share an
    // entry), adding it with `add` the first time.
    template <typename Add>
    static int indexOf(const fs::path& file, std::map<fs::path, int>& index, Add add) {
        std::error_code ignored;
        fs::path key = fs::weakly_canonical(file, ignored);
        if (key.empty()) key = file;
        auto it = index.find(key);
        if (it != index.end()) return it->second;
        int added = add(key);
        index.emplace(key, added);
        return added;
    }

    const Diagnostics& diagnostics_;
    const LoadOptions& options_;
    Scene& scene_;
    std::map<fs::path, int> imageIndex_, meshIndex_;
    CsgBuild* csg_ = nullptr;  // the csg object being flattened, if any
};

// ---------------------------------------------------------------------------------------

// Runs `parse`, one of the XmlTree::parse; what is wrong with the XML becomes an
// InputError in the loader's words.
template <typename Parse>
XmlTree parseXml(const Diagnostics& diagnostics, Parse parse) {
    try {
        return parse();
    } catch (const XmlError& e) {
        switch (e.kind) {
            case XmlError::Kind::Empty:
                diagnostics.error(0, "the file is empty", "give a CS123 scene file (<scenefile> ... </scenefile>)");
            case XmlError::Kind::NoElement:
                diagnostics.error(0, "the file has no XML element", "give a CS123 scene file");
            case XmlError::Kind::TooDeep:
                diagnostics.error(e.line, e.what(), "flatten the hierarchy (fewer levels of nested trees)");
            case XmlError::Kind::TooLarge:
                diagnostics.error(e.line, e.what(), "split the scene, or place repeated parts with masters");
            case XmlError::Kind::Malformed:
                break;
        }
        diagnostics.error(e.line, std::string("malformed XML: ") + e.what(), "fix the XML syntax at that line");
    }
}

// The scene's root tree; a file without trees is an empty scene.
NamedTree* findRoot(std::map<std::string, NamedTree>& trees, int scenefileLine, const Diagnostics& diagnostics) {
    if (trees.empty()) {
        diagnostics.warning(scenefileLine, "the scene has no <object type=\"tree\" name=\"root\">; it is empty");
        return nullptr;
    }
    auto it = trees.find("root");
    if (it == trees.end())
        diagnostics.error(scenefileLine, "no tree named 'root' (the scene)",
                          "name the scene's top-level tree <object type=\"tree\" name=\"root\">");
    return &it->second;
}

// Passes 1 to 3 over the parsed XML (the header comment).
Scene loadSceneFromTree(XmlTree tree, const fs::path& file, const LoadOptions& options,
                        const Diagnostics& diagnostics) {
    const XmlElement scenefile = tree.root();  // a parsed tree always has one
    Scene scene;
    scene.sourceFile = file;
    FileSearch search{options.searchPaths, file.parent_path()};
    SceneParser parser(diagnostics, search, scene);
    parser.parseDocument(scenefile);
    // The parsed graph holds everything the later passes need: the XML tree goes now, and
    // the flattened scene reuses its memory.
    const int scenefileLine = scenefile.line();
    const size_t primitiveElements = parser.primitiveElements();
    tree.clear();

    InstanceCounter counter(diagnostics, parser.trees());
    counter.countAll();
    NamedTree* root = findRoot(parser.trees(), scenefileLine, diagnostics);
    if (!root) return scene;
    if (root->instances > options.maxPrimitives)
        diagnostics.error(root->line,
                          "the scene flattens to " + std::to_string(root->instances) +
                              " primitive instances, more than the limit of " +
                              std::to_string(options.maxPrimitives),
                          "use fewer levels of masters, or raise the limit with --max-primitives");
    // Estimated from the count before a single instance is made (memory_limits.h).
    if (auto shortfall = hostMemoryShortfall(root->instances * kHostBytesPerInstance))
        diagnostics.error(root->line,
                          "the scene flattens to " + std::to_string(root->instances) + " primitive instances, which " +
                              *shortfall,
                          "use fewer levels of masters or a machine with more memory");

    scene.primitives.reserve(root->instances);
    // One material per primitive element used, at most.
    scene.materials.reserve(size_t(std::min<uint64_t>(primitiveElements, root->instances)));
    Flattener(diagnostics, options, scene).flatten(root->tree, Affine::identity(), Affine::identity());
    return scene;
}

}  // namespace

Scene loadSceneFromText(const std::string& xml, const fs::path& file, const LoadOptions& options) {
    Diagnostics diagnostics(file.string(), options);
    XmlTree tree = parseXml(diagnostics, [&] { return XmlTree::parse(xml, kMaxElementDepth); });
    return loadSceneFromTree(std::move(tree), file, options, diagnostics);
}

Scene loadScene(const fs::path& file, const LoadOptions& options) {
    std::error_code ec;
    if (fs::is_directory(file, ec))  // an ifstream opens a folder and reads nothing: "empty"
        throw InputError(file.string() + ": error: this is a folder, not a scene file; give the path of a .xml "
                                         "scene file (e.g. " + (file / "scene.xml").string() + ")");
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw InputError(file.string() + ": error: cannot open the scene file (" + std::strerror(errno) +
                         "); check the path");
    // Read and parsed a piece at a time (xml_tree.h): the text of a large flat scene, tens
    // of megabytes, is never held whole. A FIFO or a device is read like a file, to its end.
    Diagnostics diagnostics(file.string(), options);
    const XmlSource read = [&](char* buffer, size_t capacity) {
        in.read(buffer, std::streamsize(capacity));
        if (in.bad())
            throw InputError(file.string() + ": error: the scene file could not be read to its end; check the disk");
        return size_t(in.gcount());
    };
    // The file's size sizes the tree's arrays up front (unknown for a FIFO or a device).
    std::uintmax_t size = fs::is_regular_file(file, ec) ? fs::file_size(file, ec) : 0;
    if (ec) size = 0;
    XmlTree tree = parseXml(diagnostics, [&] { return XmlTree::parse(read, kMaxElementDepth, size_t(size)); });
    return loadSceneFromTree(std::move(tree), file, options, diagnostics);
}

}  // namespace ray
