// The scene document (scene_document.h): its copies, its places and paths, its text.
#include "scene/scene_document.h"

#include <charconv>
#include <cmath>
#include <set>

#include "core/atomic_file.h"

namespace fs = std::filesystem;

namespace ray {

// ---------------------------------------------------------------------------------------
// Transforms

TransformOp TransformOp::matrix(const Affine& m) {
    TransformOp op;
    op.kind = TransformKind::Matrix;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) op.v[size_t(4 * r + c)] = m.m[r][c];
    return op;
}

std::optional<std::string> TransformOp::whySingular() const {
    switch (kind) {
        case TransformKind::Rotate:
            if (v[0] == 0 && v[1] == 0 && v[2] == 0) return "the rotation axis is zero";
            break;
        case TransformKind::Scale:
            if (v[0] == 0 || v[1] == 0 || v[2] == 0)
                return "a zero scale (a scale of 0 on an axis) flattens what it holds to nothing";
            break;
        case TransformKind::Matrix: {
            for (double number : v)
                if (!std::isfinite(number)) return "the matrix holds a number that is not finite";
            const auto [to, from] = affine();
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c)
                    if (!std::isfinite(to.m[r][c]) || !std::isfinite(from.m[r][c]))
                        return "the matrix is singular (it flattens what it holds)";
            break;
        }
        case TransformKind::Translate: break;
    }
    return std::nullopt;
}

std::pair<Affine, Affine> TransformOp::affine() const {
    const Vec3 xyz{v[0], v[1], v[2]};
    switch (kind) {
        case TransformKind::Translate:
            return {Affine::translation(xyz), Affine::translation(-xyz)};
        case TransformKind::Rotate:
            return {Affine::rotation(xyz, v[3]), Affine::rotation(xyz, -v[3])};
        case TransformKind::Scale:
            return {Affine::scaling(xyz), Affine::scaling({1 / xyz.x, 1 / xyz.y, 1 / xyz.z})};
        case TransformKind::Matrix:
            break;
    }
    Affine m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = v[size_t(4 * r + c)];
    return {m, m.inverse()};
}

// M = T1 · T2 · … · Tn: the last transform listed acts on the objects first.
void composeBlock(Block& block) {
    block.toParent = Affine::identity();
    block.fromParent = Affine::identity();
    for (const TransformOp& op : block.transforms) {
        auto [to, from] = op.affine();
        block.toParent = block.toParent * to;
        block.fromParent = from * block.fromParent;
    }
}

// ---------------------------------------------------------------------------------------
// The document

SceneDocument::SceneDocument(const SceneDocument& other)
    : file(other.file), globals(other.globals), camera(other.camera), lights(other.lights), trees(other.trees),
      treeOrder(other.treeOrder), scenefileLine(other.scenefileLine), primitiveElements(other.primitiveElements),
      nextObjectId(other.nextObjectId), nextBlockId(other.nextBlockId) {
    resolveMasters();  // the copied references point into `other`
}

SceneDocument& SceneDocument::operator=(const SceneDocument& other) {
    if (this != &other) *this = SceneDocument(other);
    return *this;
}

namespace {

template <class Visit>
void forEachMaster(TreeNode& node, Visit& visit) {
    for (Block& block : node.blocks)
        for (SceneItem& item : block.items) {
            if (auto* master = std::get_if<MasterReference>(&item)) visit(*master);
            else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) forEachMaster(**subtree, visit);
            else if (auto* csg = std::get_if<Box<CsgNode>>(&item))
                for (TreeNode& operand : (*csg)->operands) forEachMaster(operand, visit);
        }
}

}  // namespace

void SceneDocument::resolveMasters() {
    auto resolve = [this](MasterReference& master) {
        auto it = trees.find(master.name);
        master.target = it == trees.end() ? nullptr : &it->second;
    };
    for (auto& [name, tree] : trees) forEachMaster(tree.tree, resolve);
}

NamedTree& SceneDocument::rootToSet() {
    auto [it, added] = trees.try_emplace("root");
    if (added) {
        it->second.name = "root";
        treeOrder.push_back("root");
    }
    return it->second;
}

// ---------------------------------------------------------------------------------------
// Places

namespace {

// Walks a document in its order, with the place of every block and object.
class Walker {
public:
    std::function<bool(Block&, const DocumentPlace&)> onBlock;  // true: stop
    std::function<bool(PrimitiveNode&, const DocumentPlace&)> onObject;

    void walk(SceneDocument& document) {
        for (NamedTree* tree : treesInOrder(document)) {
            place_.tree = tree;
            place_.blocks.clear();
            if (walk(tree->tree, tree->name)) return;
        }
    }

    static std::vector<NamedTree*> treesInOrder(SceneDocument& document) {
        std::vector<NamedTree*> trees;
        std::set<std::string> listed;
        for (const std::string& name : document.treeOrder) {
            auto it = document.trees.find(name);
            if (it != document.trees.end() && listed.insert(name).second) trees.push_back(&it->second);
        }
        for (auto& [name, tree] : document.trees)
            if (!listed.count(name)) trees.push_back(&tree);
        return trees;
    }

private:
    bool walk(TreeNode& node, const std::string& prefix) {
        for (size_t b = 0; b < node.blocks.size(); ++b) {
            Block& block = node.blocks[b];
            const std::string blockPath = prefix + "/transblock[" + std::to_string(b) + "]";
            place_.blocks.push_back(&block);
            place_.block = &block;
            place_.item = 0;
            place_.path = blockPath;
            if (onBlock && onBlock(block, place_)) return true;
            for (size_t i = 0; i < block.items.size(); ++i) {
                SceneItem& item = block.items[i];
                const std::string itemPath = blockPath + "/object[" + std::to_string(i) + "]";
                if (auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                    if (onObject) {
                        place_.block = &block;
                        place_.item = i;
                        place_.path = itemPath;
                        if (onObject(*primitive, place_)) return true;
                    }
                } else if (auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                    if (walk(**subtree, itemPath)) return true;
                } else if (auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                    for (size_t k = 0; k < (*csg)->operands.size(); ++k)
                        if (walk((*csg)->operands[k], itemPath + "/operand[" + std::to_string(k) + "]")) return true;
                }
            }
            place_.blocks.pop_back();
        }
        return false;
    }

    DocumentPlace place_;
};

}  // namespace

std::optional<DocumentPlace> findObject(SceneDocument& document, int id) {
    std::optional<DocumentPlace> found;
    Walker walker;
    walker.onObject = [&](PrimitiveNode& node, const DocumentPlace& place) {
        if (node.id == id) found = place;
        return found.has_value();
    };
    walker.walk(document);
    return found;
}

std::optional<DocumentPlace> findBlock(SceneDocument& document, int id) {
    std::optional<DocumentPlace> found;
    Walker walker;
    walker.onBlock = [&](Block& block, const DocumentPlace& place) {
        if (block.id == id) found = place;
        return found.has_value();
    };
    walker.walk(document);
    return found;
}

void forEachObject(SceneDocument& document, const std::function<void(PrimitiveNode&, const DocumentPlace&)>& visit) {
    Walker walker;
    walker.onObject = [&](PrimitiveNode& node, const DocumentPlace& place) {
        visit(node, place);
        return false;
    };
    walker.walk(document);
}

void forEachBlock(SceneDocument& document, const std::function<void(Block&, const DocumentPlace&)>& visit) {
    Walker walker;
    walker.onBlock = [&](Block& block, const DocumentPlace& place) {
        visit(block, place);
        return false;
    };
    walker.walk(document);
}

std::pair<Affine, Affine> composedPlacement(const std::vector<Block*>& blocks) {
    Affine to = Affine::identity(), from = Affine::identity();
    for (const Block* block : blocks) {  // as the flattener composes, outermost first
        to = to * block->toParent;
        from = block->fromParent * from;
    }
    return {to, from};
}

// ---------------------------------------------------------------------------------------
// Text

namespace {

// The shortest text that reads back as the same double (std::to_chars), so that a saved
// scene loads to the same bits.
std::string number(double value) {
    char buffer[64];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    return ec == std::errc() ? std::string(buffer, end) : std::to_string(value);
}

std::string escaped(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

const char* csgOperationName(CsgStepKind kind) {
    switch (kind) {
        case CsgStepKind::Intersection: return "intersection";
        case CsgStepKind::Difference: return "difference";
        default: return "union";
    }
}

class Writer {
public:
    Writer(const SceneDocument& document, const Resources& resources, const fs::path& target)
        : document_(document), resources_(resources) {
        std::error_code ec;
        folder_ = fs::weakly_canonical(fs::absolute(target, ec).parent_path(), ec);
    }

    std::string text() {
        out_ += "<scenefile>\n";
        writeGlobals();
        writeCamera();
        for (size_t i = 0; i < document_.lights.size(); ++i) writeLight(i, document_.lights[i]);
        // The Walker's order: the file's, then trees made in code.
        for (NamedTree* tree : Walker::treesInOrder(const_cast<SceneDocument&>(document_))) {
            out_ += "  <object type=\"tree\" name=\"" + escaped(tree->name) + "\">\n";
            writeTree(tree->tree, 2);
            out_ += "  </object>\n";
        }
        out_ += "</scenefile>\n";
        return std::move(out_);
    }

private:
    void line(int depth, const std::string& text) { out_ += std::string(size_t(2 * depth), ' ') + text + "\n"; }

    void single(int depth, const char* name, double v) { line(depth, std::string("<") + name + " v=\"" + number(v) + "\"/>"); }

    void xyz(int depth, const char* name, const Vec3& v, const char* x = "x", const char* y = "y", const char* z = "z") {
        line(depth, std::string("<") + name + " " + x + "=\"" + number(v.x) + "\" " + y + "=\"" + number(v.y) + "\" " +
                        z + "=\"" + number(v.z) + "\"/>");
    }

    void writeGlobals() {
        const GlobalCoefficients& g = document_.globals;
        line(1, "<globaldata>");
        single(2, "ambientcoeff", g.ka);
        single(2, "diffusecoeff", g.kd);
        single(2, "specularcoeff", g.ks);
        single(2, "transparentcoeff", g.kt);
        line(1, "</globaldata>");
    }

    void writeCamera() {
        const Camera& c = document_.camera;
        line(1, "<cameradata>");
        xyz(2, "pos", c.position);
        xyz(2, "look", c.look);
        xyz(2, "up", c.up);
        single(2, "heightangle", c.heightAngleDegrees);
        if (c.aperture != 0) single(2, "aperture", c.aperture);
        if (c.focalLength != 0) single(2, "focallength", c.focalLength);
        line(1, "</cameradata>");
    }

    void writeLight(size_t index, const Light& l) {
        line(1, "<lightdata>");
        single(2, "id", double(index));
        line(2, std::string("<type v=\"") + lightTypeName(l.type) + "\"/>");
        xyz(2, "color", l.color, "r", "g", "b");
        xyz(2, "function", l.attenuation, "v1", "v2", "v3");
        xyz(2, "position", l.position);
        xyz(2, "direction", l.direction);
        single(2, "angle", l.angleDegrees);
        single(2, "penumbra", l.penumbraDegrees);
        single(2, "radius", l.radius);
        single(2, "width", l.width);
        single(2, "height", l.height);
        line(1, "</lightdata>");
    }

    void writeTree(const TreeNode& tree, int depth) {
        for (const Block& block : tree.blocks) writeBlock(block, depth);
    }

    void writeBlock(const Block& block, int depth) {
        line(depth, "<transblock>");
        for (const TransformOp& op : block.transforms) writeTransform(op, depth + 1);
        if (block.motion != Vec3{}) xyz(depth + 1, "motion", block.motion);
        for (const SceneItem& item : block.items) writeItem(item, depth + 1);
        line(depth, "</transblock>");
    }

    void writeTransform(const TransformOp& op, int depth) {
        const Vec3 v{op.v[0], op.v[1], op.v[2]};
        switch (op.kind) {
            case TransformKind::Translate: xyz(depth, "translate", v); return;
            case TransformKind::Scale: xyz(depth, "scale", v); return;
            case TransformKind::Rotate:
                line(depth, "<rotate x=\"" + number(v.x) + "\" y=\"" + number(v.y) + "\" z=\"" + number(v.z) +
                                "\" angle=\"" + number(op.v[3]) + "\"/>");
                return;
            case TransformKind::Matrix:
                line(depth, "<matrix>");
                for (int r = 0; r < 4; ++r) {
                    std::string row = "<row" + std::to_string(r);
                    for (int c = 0; c < 4; ++c)
                        row += " v" + std::to_string(c + 1) + "=\"" +
                               (r < 3 ? number(op.v[size_t(4 * r + c)]) : std::string(c == 3 ? "1" : "0")) + "\"";
                    line(depth + 1, row + "/>");
                }
                line(depth, "</matrix>");
                return;
        }
    }

    void writeItem(const SceneItem& item, int depth) {
        if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) {
            writePrimitive(*primitive, depth);
        } else if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
            line(depth, "<object type=\"tree\">");
            writeTree(**subtree, depth + 1);
            line(depth, "</object>");
        } else if (const auto* master = std::get_if<MasterReference>(&item)) {
            line(depth, "<object type=\"master\" name=\"" + escaped(master->name) + "\"/>");
        } else {
            const CsgNode& csg = *std::get<Box<CsgNode>>(item);
            line(depth, std::string("<object type=\"csg\" operation=\"") + csgOperationName(csg.operation) + "\">");
            for (const TreeNode& operand : csg.operands) {
                if (operand.blocks.size() == 1) {
                    writeBlock(operand.blocks.front(), depth + 1);
                } else {  // not made by the loader; one operand all the same
                    line(depth + 1, "<transblock>");
                    line(depth + 2, "<object type=\"tree\">");
                    writeTree(operand, depth + 3);
                    line(depth + 2, "</object>");
                    line(depth + 1, "</transblock>");
                }
            }
            line(depth, "</object>");
        }
    }

    // The path to write for a file the scene names: relative to the saved file's folder.
    std::string reference(const fs::path& file) const {
        std::error_code ec;
        fs::path absolute = fs::weakly_canonical(fs::absolute(file, ec), ec);
        fs::path relative = absolute.lexically_relative(folder_);
        return escaped((relative.empty() ? absolute : relative).generic_string());
    }

    [[noreturn]] static void unsaveable(const PrimitiveNode& node, const char* what) {
        throw InputError(std::string("error: object ") + std::to_string(node.id) + " uses a " + what +
                         " made in memory, which a scenefile cannot hold; make it from a file to save the scene");
    }

    std::string imageFile(const PrimitiveNode& node, const std::optional<ImageReference>& file,
                          const std::string& missing, int image, const char* what) const {
        if (file) return reference(file->file);
        if (!missing.empty()) return escaped(missing);
        if (image < 0) return "";
        if (size_t(image) >= resources_.imageFiles.size() || resources_.imageFiles[size_t(image)] == "<memory>")
            unsaveable(node, what);
        return reference(resources_.imageFiles[size_t(image)]);
    }

    void writePrimitive(const PrimitiveNode& node, int depth) {
        std::string open = std::string("<object type=\"primitive\" name=\"") + primitiveTypeName(node.type) + "\"";
        if (node.type == PrimitiveType::Mesh) {
            if (node.files && !node.files->meshFile.empty()) open += " meshfile=\"" + reference(node.files->meshFile) + "\"";
            else if (node.mesh >= 0 && size_t(node.mesh) < resources_.meshFiles.size() &&
                     resources_.meshFiles[size_t(node.mesh)] != "<memory>")
                open += " meshfile=\"" + reference(resources_.meshFiles[size_t(node.mesh)]) + "\"";
            else
                unsaveable(node, "mesh");
        }
        line(depth, open + ">");
        const Material& m = node.material;
        const Material defaults;
        const int d = depth + 1;
        if (m.diffuse != defaults.diffuse) xyz(d, "diffuse", m.diffuse, "r", "g", "b");
        if (m.ambient != defaults.ambient) xyz(d, "ambient", m.ambient, "r", "g", "b");
        if (m.specular != defaults.specular) xyz(d, "specular", m.specular, "r", "g", "b");
        if (m.reflective != defaults.reflective) xyz(d, "reflective", m.reflective, "r", "g", "b");
        if (m.transparent != defaults.transparent) xyz(d, "transparent", m.transparent, "r", "g", "b");
        if (m.emissive != defaults.emissive) xyz(d, "emissive", m.emissive, "r", "g", "b");
        if (m.shininess != defaults.shininess) single(d, "shininess", m.shininess);
        if (m.ior != defaults.ior) single(d, "ior", m.ior);
        if (m.blend != defaults.blend) single(d, "blend", m.blend);
        static const PrimitiveFiles kNone;
        const PrimitiveFiles& files = node.files ? *node.files : kNone;
        writeMap(d, "texture", imageFile(node, files.texture, files.missingTexture, m.texture.image, "texture"),
                 m.texture);
        writeMap(d, "bumpmap", imageFile(node, files.bumpMap, files.missingBumpMap, m.bumpMap.image, "bump map"),
                 m.bumpMap);
        line(depth, "</object>");
    }

    void writeMap(int depth, const char* name, const std::string& file, const TextureMap& map) {
        if (file.empty()) return;
        line(depth, std::string("<") + name + " file=\"" + file + "\" u=\"" + number(map.repeatU) + "\" v=\"" +
                        number(map.repeatV) + "\"/>");
    }

    const SceneDocument& document_;
    const Resources& resources_;
    fs::path folder_;
    std::string out_;
};

}  // namespace

std::string documentToText(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    return Writer(document, resources, target).text();
}

void saveDocument(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    writeFileAtomically(target, documentToText(document, resources, target));
}

}  // namespace ray
