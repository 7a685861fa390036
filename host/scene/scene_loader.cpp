// Reading a CS123 scenefile (SPEC §1), XML or the course's JSON (SPEC §7), into a flattened
// Scene. A JSON file is read into the same scene document (scene/json_scene_reader.h), and
// passes 2 and 3 below are the same for both; which format a file is, is decided here alone
// (sceneFormatOf).
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
//
// Each pass is a file of its own: scene_loader_parse.cpp, scene_loader_count.cpp and
// scene_loader_flatten.cpp, sharing the parsed graph of scene_loader_passes.h.
#include "scene/scene_loader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/memory_limits.h"
#include "scene/json_scene_reader.h"
#include "scene/json_splices.h"
#include "scene/scene_loader_passes.h"
#include "scene/value_text.h"
#include "scene/xml_plain_reader.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

using loader::Diagnostics;

bool isRegular(const fs::path& file) {
    std::error_code ec;
    return fs::is_regular_file(file, ec);
}

// A folder, or a file that cannot be opened: the same words for both formats.
std::ifstream openSceneFile(const fs::path& file, const Diagnostics& diagnostics) {
    std::error_code ec;
    if (fs::is_directory(file, ec))  // an ifstream opens a folder and reads nothing: "empty"
        diagnostics.fileError("this is a folder, not a scene file",
                              "give the path of a .xml or .json scene file (e.g. " +
                                  quotedForMessage((file / "scene.xml").string()) + ")");
    std::ifstream in(file, std::ios::binary);
    if (!in) diagnostics.fileError(std::string("cannot open the scene file (") + std::strerror(errno) + ")", "check the path");
    return in;
}

// The first bytes of a file, for its format.
std::string fileStart(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::string start(256, '\0');
    in.read(start.data(), std::streamsize(start.size()));
    start.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
    return start;
}

// A FIFO or a device is not peeked at (its bytes are the parse's): its name says.
SceneFormat formatOfFile(const fs::path& file) {
    return sceneFormatOf(file, isRegular(file) ? fileStart(file) : std::string());
}

// A JSON file's text, whole (the course's scenes are kilobytes; the reader needs it all).
std::string readJsonFile(const fs::path& file, const Diagnostics& diagnostics) {
    std::ifstream in = openSceneFile(file, diagnostics);
    std::string text;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) text.append(buffer, size_t(in.gcount()));
    if (in.bad()) diagnostics.fileError("the scene file could not be read to its end", "check the disk");
    return text;
}

// Pass 1 for a JSON scene (scene/json_scene_reader.h): the document, with its ids.
SceneDocument jsonDocument(std::string_view text, const fs::path& file, const Diagnostics& diagnostics) {
    SceneDocument document;
    document.file = file;
    document.format = SceneFormat::Json;
    loader::readJsonSceneDocument(text, diagnostics, document);
    assignNodeIds(document);
    // Its text and the document as read, which a save compares it with (json_splices.h).
    document.jsonSource = std::make_shared<const JsonSource>(std::string(text), document);
    return document;
}

// The flattened scene takes the document's images and meshes; the document goes.
Scene flattenAndRelease(SceneDocument document, const LoadOptions& options, const Diagnostics& diagnostics) {
    Resources resources;
    Scene scene = loader::flattenWithDiagnostics(document, resources, diagnostics, options);
    scene.images = std::move(resources.images);
    scene.imageFiles = std::move(resources.imageFiles);
    scene.meshes = std::move(resources.meshes);
    scene.meshFiles = std::move(resources.meshFiles);
    return scene;
}

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

// Pass 1 over the parsed XML: the document.
SceneDocument documentFromRoot(XmlElement root, const fs::path& file, const LoadOptions& options,
                               const Diagnostics& diagnostics, bool keepTransforms = true) {
    SceneDocument document;
    document.file = file;
    FileSearch search{options.searchPaths, file.parent_path()};
    loader::parseSceneDocument(root, diagnostics, search, document, keepTransforms);
    if (document.trees.empty())
        diagnostics.warning(document.scenefileLine,
                            "the scene has no <object type=\"tree\" name=\"root\">; it is empty");
    return document;
}

// Passes 1 to 3 (the header comment); the flattened scene takes the loaded images and
// meshes, the document goes.
Scene loadSceneFromTree(XmlTree tree, const fs::path& file, const LoadOptions& options,
                        const Diagnostics& diagnostics) {
    Resources resources;
    Scene scene;
    {
        // Flattened and dropped: neither the text nor the transforms as written, for saving,
        // are kept.
        SceneDocument document = documentFromRoot(tree.root(), file, options, diagnostics, false);
        tree.clear();
        scene = loader::flattenWithDiagnostics(document, resources, diagnostics, options);
    }
    scene.images = std::move(resources.images);
    scene.imageFiles = std::move(resources.imageFiles);
    scene.meshes = std::move(resources.meshes);
    scene.meshFiles = std::move(resources.meshFiles);
    return scene;
}

// The text of a file read as `bytes` and parsed as `tree` (with spans): in UTF-8, as a
// save splices it (source_text.h). A file in another encoding is turned into UTF-8 and
// parsed again from that, its elements' places being those of the UTF-8 text.
std::shared_ptr<const SourceText> sourceTextOf(std::string bytes, XmlTree tree, const Diagnostics& diagnostics) {
    const TextEncoding encoding = encodingOf(bytes);
    if (encoding == TextEncoding::Utf8) return std::make_shared<const SourceText>(std::move(bytes), std::move(tree));
    tree.clear();
    std::string text = toUtf8(bytes, encoding);
    XmlTree utf8 = parseXml(diagnostics, [&] { return XmlTree::parseUtf8(text, kMaxElementDepth, true); });
    return std::make_shared<const SourceText>(std::move(text), std::move(utf8), encoding, std::move(bytes));
}

// A document that keeps its text (scene_document.h): pass 1 over `bytes`, parsed with the
// place of every element.
SceneDocument documentWithText(std::string bytes, XmlTree tree, const fs::path& file, const LoadOptions& options,
                               const Diagnostics& diagnostics) {
    auto source = sourceTextOf(std::move(bytes), std::move(tree), diagnostics);
    SceneDocument document = documentFromRoot(source->tree().root(), file, options, diagnostics);
    document.source = std::move(source);
    assignNodeIds(document);  // the editor's names for trees, placements, csg objects and lights
    return document;
}

// A regular file's bytes, whole, into `text`.
void readWholeFile(std::ifstream& in, std::uintmax_t size, const Diagnostics& diagnostics, std::string& text) {
    text.resize(size_t(size));
    in.read(text.data(), std::streamsize(text.size()));
    text.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
    // A file that grew since its size was taken: the rest too.
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) text.append(buffer, size_t(in.gcount()));
    if (in.bad()) diagnostics.fileError("the scene file could not be read to its end", "check the disk");
}

// The file as XML, read a piece at a time: the text of a large flat scene, tens of
// megabytes, is never held whole. A regular file is read in one pass when it is plain XML
// (xml_plain_reader.h: five times expat's speed on a large flat scene), else read again
// from its start by expat; a FIFO or a device is read by expat, to its end. With `keep`,
// its bytes are kept there (read whole first), and its elements' places recorded (for a
// document's text).
XmlTree readXmlFile(const fs::path& file, const Diagnostics& diagnostics, std::string* keep = nullptr) {
    std::ifstream in = openSceneFile(file, diagnostics);
    std::error_code ec;
    const bool regular = fs::is_regular_file(file, ec);
    std::uintmax_t size = regular ? fs::file_size(file, ec) : 0;
    if (ec) size = 0;
    if (regular && keep) {
        readWholeFile(in, size, diagnostics, *keep);
        return parseXml(diagnostics, [&] { return XmlTree::parse(*keep, kMaxElementDepth, true); });
    }
    const XmlSource read = [&](char* buffer, size_t capacity) {
        in.read(buffer, std::streamsize(capacity));
        if (in.bad())
            diagnostics.fileError("the scene file could not be read to its end", "check the disk");
        if (keep) keep->append(buffer, size_t(in.gcount()));
        return size_t(in.gcount());
    };
    if (regular) {
        if (std::optional<XmlTree> plain = readPlainXml(read, size_t(size), kMaxElementDepth, false))
            return std::move(*plain);
        in.clear();
        in.seekg(0);
    }
    return parseXml(diagnostics, [&] { return XmlTree::parse(read, kMaxElementDepth, size_t(size), keep != nullptr); });
}

}  // namespace

SceneFormat sceneFormatOf(const fs::path& file, std::string_view text) {
    constexpr std::string_view kUtf8Mark = "\xEF\xBB\xBF";
    if (text.substr(0, kUtf8Mark.size()) == kUtf8Mark) text.remove_prefix(kUtf8Mark.size());
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string_view::npos && (text[first] == '{' || text[first] == '[')) return SceneFormat::Json;
    if (first != std::string_view::npos && text[first] == '<') return SceneFormat::Xml;
    const std::string extension = file.extension().string();
    return sameName(extension.c_str(), ".json") ? SceneFormat::Json : SceneFormat::Xml;
}

Scene loadSceneFromText(const std::string& xml, const fs::path& file, const LoadOptions& options) {
    Diagnostics diagnostics(file.string(), options);
    if (sceneFormatOf(file, xml) == SceneFormat::Json)
        return flattenAndRelease(jsonDocument(xml, file, diagnostics), options, diagnostics);
    XmlTree tree = parseXml(diagnostics, [&] { return XmlTree::parse(xml, kMaxElementDepth); });
    return loadSceneFromTree(std::move(tree), file, options, diagnostics);
}

Scene loadScene(const fs::path& file, const LoadOptions& options) {
    Diagnostics diagnostics(file.string(), options);
    if (formatOfFile(file) == SceneFormat::Json)
        return flattenAndRelease(jsonDocument(readJsonFile(file, diagnostics), file, diagnostics), options, diagnostics);
    return loadSceneFromTree(readXmlFile(file, diagnostics), file, options, diagnostics);
}

SceneDocument loadSceneDocument(const fs::path& file, const LoadOptions& options) {
    Diagnostics diagnostics(file.string(), options);
    if (formatOfFile(file) == SceneFormat::Json) return jsonDocument(readJsonFile(file, diagnostics), file, diagnostics);
    std::string bytes;
    XmlTree tree = readXmlFile(file, diagnostics, &bytes);
    return documentWithText(std::move(bytes), std::move(tree), file, options, diagnostics);
}

SceneDocument loadSceneDocumentFromText(const std::string& xml, const fs::path& file, const LoadOptions& options) {
    Diagnostics diagnostics(file.string(), options);
    if (sceneFormatOf(file, xml) == SceneFormat::Json) return jsonDocument(xml, file, diagnostics);
    XmlTree tree = parseXml(diagnostics, [&] { return XmlTree::parse(xml, kMaxElementDepth, true); });
    return documentWithText(xml, std::move(tree), file, options, diagnostics);
}

Scene flattenDocument(SceneDocument& document, Resources& resources, const LoadOptions& options) {
    Diagnostics diagnostics(document.file.string(), options);
    Scene scene = loader::flattenWithDiagnostics(document, resources, diagnostics, options);
    scene.images = resources.images;
    scene.imageFiles = resources.imageFiles;
    scene.meshes = resources.meshes;
    scene.meshFiles = resources.meshFiles;
    return scene;
}

namespace loader {

Scene flattenWithDiagnostics(SceneDocument& document, Resources& resources, const Diagnostics& diagnostics,
                             const LoadOptions& options) {
    Scene scene;
    scene.lineage.revision = SceneLineage::fresh();  // a scene of its own until an edit says otherwise
    scene.sourceFile = document.file;
    scene.globals = document.globals;
    scene.camera = document.camera;
    scene.lights = document.lights;
    countInstances(document.trees, diagnostics);
    auto root = document.trees.find("root");
    if (root == document.trees.end()) {
        if (document.trees.empty()) return scene;  // an empty scene (documentFromRoot warned)
        diagnostics.error(document.scenefileLine, "no tree named 'root' (the scene)",
                          "name the scene's top-level tree <object type=\"tree\" name=\"root\">");
    }
    const uint64_t instances = root->second.instances;
    const int rootLine = root->second.line;
    if (instances > options.maxPrimitives)
        diagnostics.error(rootLine,
                          "the scene flattens to " + std::to_string(instances) +
                              " primitive instances, more than the limit of " + std::to_string(options.maxPrimitives),
                          "use fewer levels of masters, or raise the limit with --max-primitives");
    // Estimated from the count before a single instance is made (memory_limits.h).
    if (auto shortfall = hostMemoryShortfall(instances * kHostBytesPerInstance))
        diagnostics.error(rootLine,
                          "the scene flattens to " + std::to_string(instances) + " primitive instances, which " +
                              *shortfall,
                          "use fewer levels of masters or a machine with more memory");
    scene.primitives.reserve(instances);
    // One material per primitive element used, at most.
    scene.materials.reserve(size_t(std::min<uint64_t>(document.primitiveElements, instances)));
    flattenScene(root->second.tree, diagnostics, options, resources, scene);
    return scene;
}

}  // namespace loader

}  // namespace ray
