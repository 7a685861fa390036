// Pass 3 of the scene loader (scene_loader.cpp): the root tree walked with composed
// transforms into the Scene's instances, materials, images and meshes.
#include "scene/scene_loader_passes.h"

#include <algorithm>

namespace ray::loader {
namespace {

// ---------------------------------------------------------------------------------------
// Pass 3: flattening

class Flattener {
public:
    Flattener(const Diagnostics& diagnostics, const LoadOptions& options, Resources& resources, Scene& scene)
        : diagnostics_(diagnostics), options_(options), resources_(resources), scene_(scene) {}

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
                else if (auto* subtree = std::get_if<Box<TreeNode>>(&item))
                    flatten(**subtree, blockToWorld, blockToObject, blockMotion);
                else if (auto* csg = std::get_if<Box<CsgNode>>(&item))
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
        // The first operand's material and object: a csg object is shaded with its first
        // operand's material, so picking it names the object whose material to edit.
        const PrimitiveInstance& first = scene_.csgOperands[size_t(object.program.front().operand)];
        instance.material = first.material;
        instance.sourceObject = first.sourceObject;
        instance.sourceLine = first.sourceLine;
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
        instance.sourceObject = node.id;
        fitObjectBox(instance, resources_.meshes);
        return instance;
    }

    // One Material per primitive element, made on its first instance.
    int materialOf(PrimitiveNode& node) {
        int& index = slot(sceneMaterial_, node.id);
        if (index > 0) return index - 1;
        Material material = node.material;
        if (node.files && node.files->texture) material.texture.image = imageOf(*node.files->texture);
        if (node.files && node.files->bumpMap) material.bumpMap.image = imageOf(*node.files->bumpMap);
        index = int(scene_.materials.size()) + 1;
        scene_.materials.push_back(material);
        return index - 1;
    }

    int meshOf(PrimitiveNode& node) {
        if (node.type != PrimitiveType::Mesh) return -1;
        if (!node.files || node.files->meshFile.empty()) return node.mesh;  // made in code
        int& index = slot(sceneMesh_, node.id);
        if (index > 0) return index - 1;
        index = 1 + indexOf(node.files->meshFile, resources_.meshIndex, [&](const fs::path& file) {
            Resources& r = resources_;
            r.meshes.push_back(loadObjMesh(file));  // an unreadable file is an InputError
            r.meshFiles.push_back(file);
            return int(r.meshFiles.size()) - 1;
        });
        return index - 1;
    }

    // The entry for object `id` (ids are dense: 0 up to the document's next id).
    static int& slot(std::vector<int>& byObject, int id) {
        if (size_t(id) >= byObject.size()) byObject.resize(size_t(id) + 1, 0);
        return byObject[size_t(id)];
    }

    // Each file is read once; one that does not decode is remembered as -1 (no texture).
    int imageOf(const ImageReference& reference) {
        return indexOf(reference.file, resources_.imageIndex, [&](const fs::path& file) {
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
            resources_.images.push_back(std::move(image));
            resources_.imageFiles.push_back(file);
            return int(resources_.images.size()) - 1;
        });
    }

    // Looks `file` up by its canonical path (so two spellings of one file share an
    // entry), adding it with `add` the first time. Each spelling is made canonical once a
    // flattening (weakly_canonical asks the file system, and a scene names one texture
    // hundreds of times).
    template <typename Add>
    int indexOf(const fs::path& file, std::map<fs::path, int>& index, Add add) {
        auto [known, isNew] = canonical_.try_emplace(file);
        if (isNew) {
            std::error_code ignored;
            known->second = fs::weakly_canonical(file, ignored);
            if (known->second.empty()) known->second = file;
        }
        const fs::path& key = known->second;
        auto it = index.find(key);
        if (it != index.end()) return it->second;
        int added = add(key);
        index.emplace(key, added);
        return added;
    }

    const Diagnostics& diagnostics_;
    const LoadOptions& options_;
    Resources& resources_;
    Scene& scene_;
    // By object id: its index in scene.materials, in resources_.meshes, + 1 (0: not yet).
    std::vector<int> sceneMaterial_, sceneMesh_;
    std::map<fs::path, fs::path> canonical_;
    CsgBuild* csg_ = nullptr;  // the csg object being flattened, if any
};

}  // namespace

void flattenScene(TreeNode& root, const Diagnostics& diagnostics, const LoadOptions& options, Resources& resources,
                  Scene& scene) {
    Flattener(diagnostics, options, resources, scene).flatten(root, Affine::identity(), Affine::identity());
}

}  // namespace ray::loader
