// The splices of a course JSON scene's save (json_splices.h).
#include "scene/json_splices.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>

#include "scene/canonical_writer.h"
#include "scene/json_scene_reader.h"
#include "scene/json_writer.h"
#include "scene/value_text.h"

namespace fs = std::filesystem;

namespace ray {

JsonSource::JsonSource(std::string textRead, const SceneDocument& documentRead)
    : text(std::move(textRead)), tree(JsonTree::parse(text, kMaxJsonDepth)), asRead(documentRead) {
    parents.assign(tree.valueCount(), 0);
    for (uint32_t i = 0; i < tree.valueCount(); ++i) {
        const JsonValue value = tree.at(i);
        if (value.isArray() || value.isObject())
            for (JsonValue child = value.first(); child; child = child.next()) parents[child.index()] = i;
    }
    if (text.find("\r\n") != std::string::npos) newline = "\r\n";
    asRead.jsonSource.reset();  // the document as read keeps no text of its own
}

namespace {

// A string as JSON writes it, in double quotes.
std::string jsonString(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            static const char* hex = "0123456789abcdef";
            out += "\\u00";
            out += hex[(c >> 4) & 0xf];
            out += hex[c & 0xf];
        } else {
            out += c;
        }
    }
    return out + "\"";
}

// What the format cannot hold, and what to do (jsonDocumentSplices and jsonUnsaveable say it
// each in its own words).
struct Unsaveable {
    std::string what, remedy;
};

const std::string kIndentUnit = "  ";  // the course's files' step

const char* const kTransformKeys[] = {"translate", "rotate", "scale", "matrix"};  // by TransformKind

JsonValue jsonMember(JsonValue object, std::string_view key) {
    if (!object || !object.isObject()) return {};
    for (JsonValue m = object.first(); m; m = m.next())
        if (m.key() == key) return m;
    return {};
}

bool sameLight(const Light& a, const Light& b) {
    return a.type == b.type && a.color == b.color && a.attenuation == b.attenuation && a.position == b.position &&
           a.direction == b.direction && a.angleDegrees == b.angleDegrees && a.penumbraDegrees == b.penumbraDegrees &&
           a.radius == b.radius && a.width == b.width && a.height == b.height;
}

// Where `document` places the text's lights, as the reader places them (the same products in
// the same order, so that a group nothing moved gives the same bits): by light value, the
// frame of each of its placements, in the document's order of lights.
class LightPlacements {
public:
    LightPlacements(const SceneDocument& document, const JsonSource& source) : document_(document), source_(source) {
        if (auto root = document.trees.find("root"); root != document.trees.end())
            walk(root->second.tree, Affine::identity());
    }
    const std::vector<Affine>& of(SourceId light) const {
        static const std::vector<Affine> none;
        auto it = frames_.find(light);
        return it == frames_.end() ? none : it->second;
    }
    const std::map<SourceId, std::vector<Affine>>& all() const { return frames_; }

private:
    // A group's lights: none for a template placement (the file ignores its other keys).
    JsonValue lightsOf(const Block& block) const {
        if (block.source == kNoSource) return {};
        for (const SceneItem& item : block.items)
            if (std::holds_alternative<MasterReference>(item)) return {};
        return jsonMember(source_.tree.at(block.source), "lights");
    }

    bool holdsLights(const TreeNode& tree) {
        auto [it, added] = holds_.try_emplace(&tree, false);
        if (!added) return it->second;
        bool holds = false;
        for (const Block& block : tree.blocks) {
            const JsonValue lights = lightsOf(block);
            holds = holds || (lights && lights.isArray() && lights.size() > 0);
            for (const SceneItem& item : block.items) holds = holds || holdsLights(item);
        }
        holds_[&tree] = holds;
        return holds;
    }

    const TreeNode* treeOf(const SceneItem& item) const {
        if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) return subtree->get();
        if (const auto* reference = std::get_if<MasterReference>(&item)) {
            auto it = document_.trees.find(reference->name);
            return it == document_.trees.end() ? nullptr : &it->second.tree;
        }
        return nullptr;
    }

    bool holdsLights(const SceneItem& item) {
        const TreeNode* tree = treeOf(item);
        return tree && holdsLights(*tree);
    }

    void walk(const TreeNode& tree, const Affine& parent) {
        for (const Block& block : tree.blocks) {
            const Affine frame = parent * block.toParent;
            if (const JsonValue lights = lightsOf(block); lights && lights.isArray())
                for (JsonValue light = lights.first(); light; light = light.next()) frames_[light.index()].push_back(frame);
            for (const SceneItem& item : block.items)
                if (holdsLights(item)) walk(*treeOf(item), frame);
        }
    }

    const SceneDocument& document_;
    const JsonSource& source_;
    std::map<SourceId, std::vector<Affine>> frames_;
    std::map<const TreeNode*, bool> holds_;
};

// Light value `light` as the text says it, placed by `frame` (as the reader places it).
Light placedLight(const JsonSource& source, SourceId light, const Affine& frame) {
    const SceneDocument& read = source.asRead;
    Light placed;
    for (size_t i = 0; i < read.lights.size(); ++i)
        if (read.lightSources[i] == light) {
            placed = read.lights[i];  // its frame-free fields
            break;
        }
    Vec3 direction{0, 0, -1};
    if (const JsonValue written = jsonMember(source.tree.at(light), "direction"); written && written.size() == 3) {
        int i = 0;
        for (JsonValue item = written.first(); item; item = item.next(), ++i) direction[i] = item.number();
    }
    placed.position = frame.transformPoint({0, 0, 0});
    placed.direction = frame.transformVector(direction);
    return placed;
}

class JsonSplicer {
public:
    JsonSplicer(const SceneDocument& document, const Resources& resources, const fs::path& target)
        : doc_(document), src_(*document.jsonSource), was_(src_.asRead), resources_(resources), target_(target),
          // Paths are relative to the folder above the scene's folder (SPEC §7).
          references_(fs::absolute(target).parent_path()) {}

    std::vector<Splice> splices() {
        indexDocument(doc_, now_);
        indexDocument(was_, then_);
        globals();
        camera();
        trees();
        lights();
        removeUnclaimed();
        finishNewItems();
        finishRemovals();
        return withoutNested();
    }

private:
    // -----------------------------------------------------------------------------------
    // The documents' nodes by the JSON value they were read from

    struct Index {
        std::unordered_map<SourceId, const PrimitiveNode*> primitives;
        std::unordered_map<SourceId, const Block*> blocks;
        std::unordered_map<SourceId, SourceId> blockOf;     // a primitive's or a block's enclosing block (kNoSource: none)
        std::unordered_map<int, const Block*> parentBlock;  // by block id: the enclosing block, or a template's placer
        std::unordered_map<std::string, int> placements;    // by template: how many blocks place it
        std::unordered_map<std::string, const Block*> placer;
        std::unordered_map<int, const Block*> blocksById;
        std::unordered_map<int, std::string> treeOf;        // by block id: the top-level tree holding it
    };

    static void indexDocument(const SceneDocument& document, Index& index) {
        for (const auto& [name, tree] : document.trees) indexTree(tree.tree, nullptr, name, index);
    }

    static void indexTree(const TreeNode& node, const Block* parent, const std::string& tree, Index& index) {
        for (const Block& block : node.blocks) {
            index.parentBlock[block.id] = parent;
            index.blocksById[block.id] = &block;
            index.treeOf[block.id] = tree;
            if (block.source != kNoSource) {
                index.blocks[block.source] = &block;
                index.blockOf[block.source] = parent ? parent->source : kNoSource;
            }
            for (const SceneItem& item : block.items) {
                if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                    if (primitive->source != kNoSource) {
                        index.primitives[primitive->source] = primitive;
                        index.blockOf[primitive->source] = block.source;
                    }
                } else if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                    indexTree(**subtree, &block, tree, index);
                } else if (const auto* reference = std::get_if<MasterReference>(&item)) {
                    ++index.placements[reference->name];
                    index.placer[reference->name] = &block;
                } else if (const auto* csg = std::get_if<Box<CsgNode>>(&item)) {
                    for (const TreeNode& operand : (*csg)->operands) indexTree(operand, &block, tree, index);
                }
            }
        }
    }

    // -----------------------------------------------------------------------------------
    // The text

    const std::string& text() const { return src_.text; }
    JsonValue value(SourceId id) const { return src_.tree.at(id); }
    JsonValue parentOf(JsonValue v) const { return src_.tree.at(src_.parents[v.index()]); }

    // Past the value starting at `offset`.
    size_t valueEnd(size_t offset) const {
        const std::string& t = text();
        size_t i = offset;
        if (t[i] == '"') return stringEnd(i);
        if (t[i] == '[' || t[i] == '{') {
            int depth = 0;
            for (; i < t.size(); ++i) {
                const char c = t[i];
                if (c == '"') {
                    i = stringEnd(i) - 1;
                } else if (c == '[' || c == '{') {
                    ++depth;
                } else if (c == ']' || c == '}') {
                    if (--depth == 0) return i + 1;
                }
            }
            return t.size();
        }
        while (i < t.size() && !std::strchr(",]} \t\r\n", t[i])) ++i;
        return i;
    }

    size_t stringEnd(size_t quote) const {
        const std::string& t = text();
        size_t i = quote + 1;
        while (i < t.size() && t[i] != '"') i += t[i] == '\\' ? 2 : 1;
        return std::min(i + 1, t.size());
    }

    // Where an item of an array, or a member of an object (its key), starts.
    size_t itemStart(JsonValue item) const { return parentOf(item).isObject() ? item.keyOffset() : item.offset(); }

    // The start of `at`'s line when only blanks come before it there; `at` otherwise.
    size_t ownLineStart(size_t at) const {
        size_t i = at;
        while (i > 0 && (text()[i - 1] == ' ' || text()[i - 1] == '\t')) --i;
        return i == 0 || text()[i - 1] == '\n' ? i : at;
    }

    // The blanks before `at` on its line when nothing else is there.
    std::optional<std::string> indentationAt(size_t at) const {
        const size_t start = ownLineStart(at);
        if (start == at && (start > 0 && text()[start - 1] != '\n')) return std::nullopt;
        return text().substr(start, at - start);
    }

    JsonValue member(JsonValue object, std::string_view key) const {
        if (!object || !object.isObject()) return {};
        for (JsonValue m = object.first(); m; m = m.next())
            if (m.key() == key) return m;
        return {};
    }

    // "groups[2].primitives[0]", for messages.
    std::string placeOf(JsonValue v) const {
        std::vector<std::string> steps;  // innermost first
        for (; v.index() != 0; v = parentOf(v)) {
            const JsonValue parent = parentOf(v);
            if (parent.isObject()) {
                steps.emplace_back(v.key());
                continue;
            }
            size_t i = 0;
            for (JsonValue c = parent.first(); c && c.index() != v.index(); c = c.next()) ++i;
            std::string step = "[";
            step += std::to_string(i);
            steps.push_back(step + "]");
        }
        std::string place;
        for (auto step = steps.rbegin(); step != steps.rend(); ++step) {
            if (!place.empty() && step->front() != '[') place += '.';
            place += *step;
        }
        return place.empty() ? "the top level" : place;
    }

    [[noreturn]] void refuse(const std::string& what, const std::string& remedy) const {
        throw Unsaveable{what, remedy};
    }

    void replace(JsonValue v, std::string replacement) {
        splices_.push_back({v.offset(), valueEnd(v.offset()), std::move(replacement)});
    }

    // A new member `key` of `object`, after its last one: on a line of its own indented like
    // it when it has one, after it on its line otherwise.
    void addMember(JsonValue object, const std::string& key, const std::string& valueText) {
        JsonValue last;
        for (JsonValue m = object.first(); m; m = m.next()) last = m;
        const std::string member = jsonString(key) + ": " + valueText;
        if (!last) {
            splices_.push_back({object.offset() + 1, object.offset() + 1, member});
            return;
        }
        const size_t at = valueEnd(last.offset());
        if (std::optional<std::string> indent = indentationAt(last.keyOffset()))
            splices_.push_back({at, at, "," + src_.newline + *indent + member});
        else
            splices_.push_back({at, at, ", " + member});
    }

    void removeMember(JsonValue object, std::string_view key) {
        if (JsonValue m = member(object, key)) removed_[object.index()].insert(m.index());
    }

    // -----------------------------------------------------------------------------------
    // Numbers, colours, vectors, strings

    std::string number(const std::string& key, double v) const { return typedNumberText(doc_, key, v); }

    std::string numbersText(const std::string& owner, const std::string& field, const double* v, size_t n,
                            size_t first = 0) const {
        std::string out = "[";
        for (size_t i = 0; i < n; ++i) out += (i ? ", " : "") + number(numberKey(owner, field, first + i), v[i]);
        return out + "]";
    }

    // The array `key` of `object` made to hold `now` where it held `was` (each number that
    // differs written over its text), or added when the object lacks it.
    void setNumbers(JsonValue object, const char* key, const double* now, const double* was, size_t n,
                    const std::string& owner, const std::string& field, size_t first = 0) {
        if (std::equal(now, now + n, was)) return;
        const JsonValue array = member(object, key);
        if (!array) return addMember(object, key, numbersText(owner, field, now, n, first));
        size_t i = 0;
        for (JsonValue item = array.first(); item && i < n; item = item.next(), ++i)
            if (now[i] != was[i]) replace(item, number(numberKey(owner, field, first + i), now[i]));
    }

    void setVec3(JsonValue object, const char* key, const Vec3& now, const Vec3& was, const std::string& owner,
                 const std::string& field) {
        const double a[3] = {now.x, now.y, now.z}, b[3] = {was.x, was.y, was.z};
        setNumbers(object, key, a, b, 3, owner, field);
    }

    void setNumber(JsonValue object, const char* key, double now, double was, const std::string& owner,
                   const std::string& field) {
        if (now == was) return;
        const std::string written = number(numberKey(owner, field, 0), now);
        if (const JsonValue v = member(object, key)) replace(v, written);
        else addMember(object, key, written);
    }

    void setString(JsonValue object, const char* key, const std::string& now) {
        if (const JsonValue v = member(object, key)) {
            if (v.isString() && v.string() == now) return;
            replace(v, jsonString(now));
        } else {
            addMember(object, key, jsonString(now));
        }
    }

    // -----------------------------------------------------------------------------------
    // globalData, cameraData

    void globals() {
        const JsonValue object = member(src_.tree.root(), "globalData");
        const GlobalCoefficients &g = doc_.globals, &w = was_.globals;
        setNumber(object, "ambientCoeff", g.ka, w.ka, "globals", "ambientcoeff");
        setNumber(object, "diffuseCoeff", g.kd, w.kd, "globals", "diffusecoeff");
        setNumber(object, "specularCoeff", g.ks, w.ks, "globals", "specularcoeff");
        setNumber(object, "transparentCoeff", g.kt, w.kt, "globals", "transparentcoeff");
    }

    void camera() {
        const JsonValue object = member(src_.tree.root(), "cameraData");
        const Camera &c = doc_.camera, &w = was_.camera;
        if (c == w) return;
        setVec3(object, "position", c.position, w.position, "camera", "pos");
        setVec3(object, "up", c.up, w.up, "camera", "up");
        setNumber(object, "heightAngle", c.heightAngleDegrees, w.heightAngleDegrees, "camera", "heightangle");
        setNumber(object, "aperture", c.aperture, w.aperture, "camera", "aperture");
        setNumber(object, "focalLength", c.focalLength, w.focalLength, "camera", "focallength");
        const JsonValue focus = member(object, "focus");
        if (!focus) return setVec3(object, "look", c.look, w.look, "camera", "look");
        if (c.look == w.look && c.position == w.position) return;
        // A focus point stays one: the point the camera now looks at.
        const Vec3 point = c.position + c.look;
        size_t i = 0;
        for (JsonValue item = focus.first(); item && i < 3; item = item.next(), ++i)
            if (!item.isNumber() || item.number() != point[int(i)]) replace(item, shortestNumber(point[int(i)]));
    }

    // -----------------------------------------------------------------------------------
    // Groups, templates, primitives

    // -----------------------------------------------------------------------------------
    // New items of an array: each written (json_writer.h) after the item before it that the
    // text keeps, on a line of its own indented like its neighbours.

    struct NewItems {
        JsonValue holder;      // the object whose member the array is
        std::string key;       // the member's key
        JsonValue array;       // none: the object has no such member yet
        JsonValue anchor;      // the last item kept so far (none: the start)
        std::vector<std::pair<JsonValue, std::string>> texts;  // by anchor
    };

    // One for each array (or missing member) of the text.
    NewItems& newItems(JsonValue holder, const std::string& key) {
        std::unique_ptr<NewItems>& slot = pending_[{holder.index(), key}];
        if (slot) return *slot;
        slot = std::make_unique<NewItems>();
        NewItems& items = *slot;
        items.holder = holder;
        items.key = key;
        items.array = member(holder, key);
        return items;
    }

    // The indentation of a member of `object` (its members' own, else one step past it).
    std::string memberIndent(JsonValue object) const {
        if (JsonValue first = object.first())
            if (std::optional<std::string> indent = indentationAt(first.keyOffset())) return *indent;
        return indentationAt(ownLineStart(object.offset())).value_or("") + kIndentUnit;
    }

    // The indentation of an item of `items` (a new array's: one step past its key's).
    std::string itemIndent(const NewItems& items) const {
        if (items.array && items.array.first())
            if (std::optional<std::string> indent = indentationAt(items.array.first().offset())) return *indent;
        return memberIndent(items.holder) + kIndentUnit;
    }

    void add(NewItems& items, std::string text) {
        items.texts.emplace_back(items.anchor, std::move(text));
        if (items.array) growing_.insert(items.array.index());
    }

    void finishNewItems() {
        for (const auto& [where, items] : pending_)
            if (!items->texts.empty()) finish(*items);
    }

    void finish(const NewItems& items) {
        const std::string& nl = src_.newline;
        const std::string indent = itemIndent(items);
        std::vector<std::string> all;
        for (const auto& [anchor, text] : items.texts) all.push_back(text);
        auto joined = [&](const std::string& separator) {
            std::string out;
            for (size_t i = 0; i < all.size(); ++i) out += (i ? separator : "") + all[i];
            return out;
        };
        if (!items.array)
            return addMember(items.holder, items.key,
                             "[" + nl + indent + joined("," + nl + indent) + nl + memberIndent(items.holder) + "]");
        const JsonValue array = items.array;
        const size_t close = valueEnd(array.offset()) - 1;
        const auto removed = removed_.find(array.index());
        const bool emptied = array.size() == 0 || (removed != removed_.end() && removed->second.size() == array.size());
        if (emptied) {  // the brackets' inside is written anew (an emptied array's removal takes it)
            const std::string closing = indentationAt(close).value_or(memberIndent(items.holder));
            if (array.size() == 0)
                splices_.push_back({array.offset() + 1, close, nl + indent + joined("," + nl + indent) + nl + closing});
            else
                splices_.push_back({array.offset() + 1, array.offset() + 1,
                                    nl + indent + joined("," + nl + indent) + nl + closing});
            return;
        }
        const bool ownLines = indentationAt(array.first().offset()).has_value();
        for (const auto& [anchor, text] : items.texts) {
            if (anchor) {
                const size_t at = valueEnd(anchor.offset());
                splices_.push_back({at, at, (ownLines ? "," + nl + indent : std::string(", ")) + text});
            } else if (ownLines) {
                const size_t at = ownLineStart(array.first().offset());
                splices_.push_back({at, at, indent + text + "," + nl});
            } else {
                splices_.push_back({array.first().offset(), array.first().offset(), text + ", "});
            }
        }
    }

    // -----------------------------------------------------------------------------------
    // Groups, templates, primitives

    void trees() {
        const JsonValue root = src_.tree.root();
        const JsonValue templates = member(root, "templateGroups");
        for (const NamedTree* tree_ : treesInFileOrder()) {
            const NamedTree& tree = *tree_;
            const std::string& name = tree.name;
            if (name == "root") {
                NewItems& groups = newItems(root, "groups");
                treeNode(tree.tree, name, groups);
                continue;
            }
            const Block* top = tree.tree.blocks.empty() ? nullptr : &tree.tree.blocks.front();
            if (tree.tree.blocks.size() == 1 && top->source != kNoSource && then_.blocks.count(top->source) &&
                templates && parentOf(value(top->source)).index() == templates.index()) {
                claim(top->source);
                newItems(root, "templateGroups").anchor = value(top->source);
                group(*top, *then_.blocks.at(top->source), value(top->source), name);
                continue;
            }
            NewItems& templateItems = newItems(root, "templateGroups");
            add(templateItems, newTemplateText(tree, itemIndent(templateItems)));
        }
    }

    // The document's trees in the file's order, then those made since.
    std::vector<const NamedTree*> treesInFileOrder() const {
        std::vector<const NamedTree*> trees;
        std::set<std::string> listed;
        for (const std::string& name : doc_.treeOrder)
            if (auto it = doc_.trees.find(name); it != doc_.trees.end() && listed.insert(name).second)
                trees.push_back(&it->second);
        for (const auto& [name, tree] : doc_.trees)
            if (!listed.count(name)) trees.push_back(&tree);
        return trees;
    }

    // A group that placed a template and now places nothing (its placement deleted) goes:
    // its text names the template still.
    bool placementDeleted(const Block& block, const Block& was) const {
        const auto placement = [](const Block& b) {
            return std::any_of(b.items.begin(), b.items.end(),
                               [](const SceneItem& item) { return std::holds_alternative<MasterReference>(item); });
        };
        return placement(was) && block.items.empty() && block.transforms.empty();
    }

    void treeNode(const TreeNode& node, const std::string& tree, NewItems& items) {
        for (const Block& block : node.blocks) {
            const auto was = then_.blocks.find(block.source);
            const bool inPlace = block.source != kNoSource && was != then_.blocks.end() && items.array &&
                                 parentOf(value(block.source)).index() == items.array.index();
            if (!inPlace) {
                add(items, newGroupText(block, itemIndent(items)));
                continue;
            }
            if (placementDeleted(block, *was->second)) continue;
            claim(block.source);
            items.anchor = value(block.source);
            group(block, *was->second, value(block.source), tree);
        }
    }

    void claim(SourceId source) { claimed_.insert(source); }

    void group(const Block& block, const Block& was, JsonValue object, const std::string& tree) {
        const std::string place = placeOf(object);
        if (!(block.motion == Vec3{0, 0, 0}))
            refuse("the group " + place + " has motion (<motion>), which a JSON scene cannot hold",
                   "set its motion to 0, or save the scene as XML");
        const MasterReference* placement = nullptr;
        NewItems& primitives = newItems(object, "primitives");
        NewItems& groups = newItems(object, "groups");
        // A JSON group lists its primitives, then its subgroups: the document's order within
        // each is kept (between the two it only decides ties, SPEC §4).
        for (const SceneItem& item : block.items) {
            if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) {
                const auto then = then_.primitives.find(primitive->source);
                const bool inPlace = primitive->source != kNoSource && then != then_.primitives.end() &&
                                     then_.blockOf.at(primitive->source) == block.source;
                if (!inPlace) {
                    add(primitives, newPrimitiveText(*primitive, itemIndent(primitives)));
                    continue;
                }
                claim(primitive->source);
                primitives.anchor = value(primitive->source);
                primitiveNode(*primitive, *then->second, value(primitive->source));
            } else if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
                treeNode(**subtree, tree, groups);
            } else if (const auto* reference = std::get_if<MasterReference>(&item)) {
                placement = reference;
            } else {
                refuse("a csg object in " + place, "a JSON scene has no csg; save the scene as XML");
            }
        }
        if (placement) {
            if (!block.transforms.empty() || block.items.size() != 1)
                refuse("the group " + place + " places template \"" + placement->name +
                           "\", so the file ignores its other keys and the edit would be lost",
                       "transform or fill the group around it instead");
            setString(object, "name", placement->name);
            return;
        }
        templateName(block, object, tree);
        transforms(block, was, object, place);
    }

    // What the text does not hold yet, written by the JSON writer in the course's style
    // (json_writer.h), at the indentation of the items around it.
    JsonWriter& writer() {
        if (!writer_) writer_.emplace(doc_, resources_, target_, TextStyle{src_.newline, kIndentUnit});
        return *writer_;
    }
    std::string newGroupText(const Block& block, const std::string& indent) { return writer().group(block, indent); }
    std::string newPrimitiveText(const PrimitiveNode& node, const std::string& indent) {
        return writer().primitive(node, indent);
    }
    std::string newTemplateText(const NamedTree& tree, const std::string& indent) {
        return writer().templateGroup(tree, indent);
    }
    std::string newLightGroupText(size_t index, const std::string& indent) { return writer().lightGroup(index, indent); }

    // A template's group is the tree of its name: a renamed tree renames it.
    void templateName(const Block& block, JsonValue object, const std::string& tree) {
        if (tree == "root") return;
        const JsonValue templates = member(src_.tree.root(), "templateGroups");
        if (templates && parentOf(object).index() == templates.index() && &block == &doc_.trees.at(tree).tree.blocks.front())
            setString(object, "name", tree);
    }

    void transforms(const Block& block, const Block& was, JsonValue object, const std::string& place) {
        if (block.transforms.size() == was.transforms.size() &&
            std::equal(block.transforms.begin(), block.transforms.end(), was.transforms.begin(),
                       [](const TransformOp& a, const TransformOp& b) { return a.kind == b.kind && a.v == b.v; }))
            return;
        // A JSON group composes T · R · S · Matrix, one of each at most, whatever its keys' order.
        for (size_t i = 1; i < block.transforms.size(); ++i)
            if (block.transforms[i].kind <= block.transforms[i - 1].kind)
                refuse("the group " + place + "'s transforms are not in the order translate, rotate, scale, matrix "
                       "with one of each at most, which is all a JSON group composes",
                       "put the transforms in that order, or nest a group for each further transform");
        const std::string owner = "block " + std::to_string(block.id);
        for (int kind = 0; kind < 4; ++kind) {
            const auto find = [kind](const Block& b) -> std::optional<std::pair<size_t, TransformOp>> {
                for (size_t i = 0; i < b.transforms.size(); ++i)
                    if (int(b.transforms[i].kind) == kind) return std::make_pair(i, b.transforms[i]);
                return std::nullopt;
            };
            const auto now = find(block), then = find(was);
            const char* key = kTransformKeys[kind];
            if (!now) {
                if (then) removeMember(object, key);
                continue;
            }
            const std::string field = "transform " + std::to_string(now->first);
            const size_t count = TransformKind(kind) == TransformKind::Rotate ? 4 : 3;
            if (TransformKind(kind) != TransformKind::Matrix) {
                const TransformOp old = then ? then->second : TransformOp{};
                if (!then) {
                    addMember(object, key, numbersText(owner, field, now->second.v.data(), count));
                    continue;
                }
                setNumbers(object, key, now->second.v.data(), old.v.data(), count, owner, field);
                continue;
            }
            matrix(object, now->second, then ? &then->second : nullptr, owner, field);
        }
    }

    // Four rows of four, the translation in the last column; the last row is 0 0 0 1.
    void matrix(JsonValue object, const TransformOp& now, const TransformOp* then, const std::string& owner,
                const std::string& field) {
        if (!then) {
            std::string rows = "[";
            for (size_t r = 0; r < 3; ++r) rows += numbersText(owner, field, now.v.data() + 4 * r, 4, 4 * r) + ", ";
            return addMember(object, "matrix", rows + "[0, 0, 0, 1]]");
        }
        const JsonValue rows = member(object, "matrix");
        size_t r = 0;
        for (JsonValue row = rows.first(); row && r < 3; row = row.next(), ++r) {
            size_t c = 0;
            for (JsonValue item = row.first(); item && c < 4; item = item.next(), ++c)
                if (now.v[4 * r + c] != then->v[4 * r + c])
                    replace(item, number(numberKey(owner, field, 4 * r + c), now.v[4 * r + c]));
        }
    }

    void primitiveNode(const PrimitiveNode& node, const PrimitiveNode& was, JsonValue object) {
        const std::string place = placeOf(object), owner = "object " + std::to_string(node.id);
        if (node.type != was.type) {
            if (node.type == PrimitiveType::Torus || node.type == PrimitiveType::Mesh || was.type == PrimitiveType::Mesh)
                refuse("the primitive " + place + " is now a " + primitiveTypeName(node.type) +
                           (node.type == PrimitiveType::Torus ? ", which a JSON scene has not"
                                                              : ", and a mesh cannot be switched in place"),
                       "JSON has cube, sphere, cylinder, cone and mesh; delete it and add one of those");
            setString(object, "type", primitiveTypeName(node.type));
        }
        const Material &m = node.material, &w = was.material;
        if (!(m.emissive == w.emissive))
            refuse("the primitive " + place + " has an emissive colour, which a JSON scene cannot hold",
                   "set emissive to 0 0 0, or save the scene as XML");
        const std::pair<const char*, Vec3 Material::*> colors[] = {{"ambient", &Material::ambient},
                                                                   {"diffuse", &Material::diffuse},
                                                                   {"specular", &Material::specular},
                                                                   {"reflective", &Material::reflective},
                                                                   {"transparent", &Material::transparent}};
        for (const auto& [key, color] : colors) setVec3(object, key, m.*color, w.*color, owner, key);
        setNumber(object, "shininess", m.shininess, w.shininess, owner, "shininess");
        setNumber(object, "ior", m.ior, w.ior, owner, "ior");
        setNumber(object, "blend", m.blend, w.blend, owner, "blend");
        imageMap(node, was, object, false);
        imageMap(node, was, object, true);
        if (node.type == PrimitiveType::Mesh) {
            const std::string now = meshFileOf(node, resources_, references_), then = meshFileOf(was, resources_, references_);
            if (now != then) setString(object, "meshFile", now);
        }
    }

    void imageMap(const PrimitiveNode& node, const PrimitiveNode& was, JsonValue object, bool bumpMap) {
        const char* fileKey = bumpMap ? "bumpMapFile" : "textureFile";
        const std::string owner = "object " + std::to_string(node.id), field = bumpMap ? "bumpmap" : "texture";
        const TextureMap &map = bumpMap ? node.material.bumpMap : node.material.texture,
                         &old = bumpMap ? was.material.bumpMap : was.material.texture;
        const std::string now = imageFileOf(node, bumpMap, resources_, references_),
                          then = imageFileOf(was, bumpMap, resources_, references_);
        if (now != then) {
            if (now.empty()) removeMember(object, fileKey);
            else setString(object, fileKey, now);
        }
        setNumber(object, bumpMap ? "bumpMapU" : "textureU", map.repeatU, old.repeatU, owner, field);
        if (map.repeatV != old.repeatV) {
            const std::string written = number(numberKey(owner, field, 1), map.repeatV);
            const char* key = bumpMap ? "bumpMapV" : "textureV";
            if (const JsonValue v = member(object, key)) replace(v, written);
            else addMember(object, key, written);
        }
    }

    // -----------------------------------------------------------------------------------
    // Lights

    // The frame of a block in the world, composed as the reader placed its lights (the same
    // products in the same order, so an unedited group gives the same bits).
    Affine worldFrame(const Block& block) const {
        std::vector<const Block*> chain;
        for (const Block* b = &block; b;) {
            chain.push_back(b);
            const Block* parent = now_.parentBlock.at(b->id);
            if (!parent) {
                const std::string& tree = now_.treeOf.at(b->id);
                if (tree != "root") {
                    const auto placer = now_.placer.find(tree);
                    parent = placer == now_.placer.end() ? nullptr : placer->second;
                }
            }
            b = parent;
        }
        Affine frame = Affine::identity();
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) frame = frame * (*it)->toParent;
        return frame;
    }

    void lights() {
        std::map<SourceId, std::vector<size_t>> now, then;  // by light value: the lights placed from it
        for (size_t i = 0; i < doc_.lights.size(); ++i) {
            const SourceId source = i < doc_.lightSources.size() ? doc_.lightSources[i] : kNoSource;
            if (source == kNoSource) {  // a group of its own at the end of the scene's
                NewItems& groups = newItems(src_.tree.root(), "groups");
                add(groups, newLightGroupText(i, itemIndent(groups)));
                continue;
            }
            now[source].push_back(i);
        }
        for (size_t i = 0; i < was_.lights.size(); ++i) then[was_.lightSources[i]].push_back(i);
        const LightPlacements placements(doc_, src_);
        for (const auto& [source, placed] : then) {
            const JsonValue object = value(source);
            const std::vector<size_t>& kept = now[source];
            const std::vector<Affine>& frames = placements.of(source);
            if (kept.empty() && frames.size() == placed.size()) {  // removed, its group kept
                removed_[parentOf(object).index()].insert(object.index());
                continue;
            }
            // Unedited, each light is where its group, as the document now places it, puts it.
            bool same = kept.size() == frames.size();
            for (size_t k = 0; same && k < kept.size(); ++k)
                same = sameLight(doc_.lights[kept[k]], placedLight(src_, source, frames[k]));
            if (same) continue;
            const JsonValue groupObject = parentOf(parentOf(object));
            if (frames.empty())
                refuse("the light " + placeOf(object) + " stays while its group " + placeOf(groupObject) +
                           " is removed",
                       "delete the light too, or keep its group");
            if (frames.size() > 1 || kept.size() != 1)
                refuse("the light " + placeOf(object) + " is one light of a template placed " +
                           std::to_string(frames.size()) + " times, and the edit changes " +
                           (kept.size() == frames.size() ? "one of its places" : "how many there are"),
                       "edit the template's light in the .json file, or give this place a light of its own");
            light(doc_.lights[kept.front()], was_.lights[placed.front()], object, groupObject, kept.front(),
                  frames.front());
        }
    }

    void light(const Light& light, const Light& was, JsonValue object, JsonValue groupObject, size_t index,
               Affine frame) {
        const std::string place = placeOf(object), owner = "light " + std::to_string(index);
        if (light.type != was.type)
            refuse("the light " + place + " is now a " + std::string(lightTypeName(light.type)) + " light" +
                       (light.type == LightType::Area ? ", which a JSON scene has not" : ""),
                   "change its \"type\" in the .json file (its keys differ by type), or delete it and add another");
        if (light.radius != was.radius || light.width != was.width || light.height != was.height)
            refuse("the light " + place + "'s radius or size changed, which a JSON light does not hold",
                   "leave them as they were, or save the scene as XML");
        const auto group = now_.blocks.find(groupObject.index());
        if (group == now_.blocks.end())
            refuse("the light " + place + " stays while its group " + placeOf(groupObject) + " is removed",
                   "delete the light too, or keep its group");
        setVec3(object, "color", light.color, was.color, owner, "color");
        if (light.type != LightType::Directional)
            setVec3(object, "attenuationCoeff", light.attenuation, was.attenuation, owner, "function");
        if (light.type == LightType::Spot) {
            setNumber(object, "angle", light.angleDegrees, was.angleDegrees, owner, "angle");
            setNumber(object, "penumbra", light.penumbraDegrees, was.penumbraDegrees, owner, "penumbra");
        }
        if (light.type != LightType::Directional && !(frame.transformPoint({0, 0, 0}) == light.position))
            frame = moveGroup(*group->second, groupObject, light, place);
        if (light.type != LightType::Point) {
            // The direction in the group's frame, written where it reads otherwise.
            const Vec3 local = frame.inverse().transformVector(light.direction);
            const JsonValue direction = member(object, "direction");
            if (!direction) {
                addMember(object, "direction", "[" + shortestNumber(local.x) + ", " + shortestNumber(local.y) + ", " +
                                                   shortestNumber(local.z) + "]");
            } else if (!(frame.transformVector(numbersOf(direction)) == light.direction)) {
                int i = 0;
                for (JsonValue item = direction.first(); item && i < 3; item = item.next(), ++i)
                    if (item.number() != local[i]) replace(item, shortestNumber(local[i]));
            }
        }
    }

    Vec3 numbersOf(JsonValue array) const {
        Vec3 v;
        int i = 0;
        for (JsonValue item = array.first(); item && i < 3; item = item.next(), ++i) v[i] = item.number();
        return v;
    }

    // A light is at its group's origin: moved, its group moves when it holds nothing else.
    Affine moveGroup(const Block& group, JsonValue groupObject, const Light& light, const std::string& place) {
        const JsonValue lights = member(groupObject, "lights");
        if (!group.items.empty() || !lights || lights.size() != 1)
            refuse("the light " + place + " would not be where the scene has it: a JSON light sits at the origin of "
                   "its group, " + placeOf(groupObject) + ", which holds more than this light",
                   "move the group instead, or put the light in a group of its own in the .json file");
        // The group's translate t such that parent · T(t) · R · S · Matrix · 0 = the light's position.
        const Block* parent = now_.parentBlock.at(group.id);
        const Affine parentFrame = parent ? worldFrame(*parent) : Affine::identity();
        Block rest;
        for (const TransformOp& op : group.transforms)
            if (op.kind != TransformKind::Translate) rest.transforms.push_back(op);
        composeBlock(rest);
        const Vec3 t = parentFrame.inverse().transformPoint(light.position) - rest.toParent.transformPoint({0, 0, 0});
        const std::string text = "[" + shortestNumber(t.x) + ", " + shortestNumber(t.y) + ", " + shortestNumber(t.z) + "]";
        if (const JsonValue translate = member(groupObject, "translate")) replace(translate, text);
        else addMember(groupObject, "translate", text);
        Block moved;
        moved.transforms.push_back(TransformOp{TransformKind::Translate, {t.x, t.y, t.z}});
        moved.transforms.insert(moved.transforms.end(), rest.transforms.begin(), rest.transforms.end());
        composeBlock(moved);
        return parentFrame * moved.toParent;
    }

    // -----------------------------------------------------------------------------------
    // Removals

    // The primitives and groups of the text that no node claims any more.
    void removeUnclaimed() {
        for (const auto& [source, node] : then_.primitives)
            if (!claimed_.count(source)) removed_[parentOf(value(source)).index()].insert(source);
        for (const auto& [source, block] : then_.blocks)
            if (!claimed_.count(source)) removed_[parentOf(value(source)).index()].insert(source);
    }

    // Each container's removed items go with their own lines: an item followed by one that
    // stays takes the text up to it; a run at the end takes the text from the end of the
    // last item that stays (its comma with it); all of them leave the brackets empty.
    void finishRemovals() {
        emptiedArraysGo();
        for (const auto& [containerIndex, items] : removed_) {
            const JsonValue container = src_.tree.at(containerIndex);
            std::vector<JsonValue> all;
            for (JsonValue item = container.first(); item; item = item.next()) all.push_back(item);
            std::vector<bool> gone(all.size());
            for (size_t i = 0; i < all.size(); ++i) gone[i] = items.count(all[i].index()) > 0;
            const auto lastKept = std::find(gone.rbegin(), gone.rend(), false);
            if (lastKept == gone.rend()) {  // none stays
                removal(container.offset() + 1, valueEnd(container.offset()) - 1);
                continue;
            }
            const size_t keptEnd = size_t(gone.rend() - lastKept);  // past the last that stays
            for (size_t i = 0; i < keptEnd; ++i)
                if (gone[i]) removal(ownLineStart(itemStart(all[i])), ownLineStart(itemStart(all[i + 1])));
            if (keptEnd < all.size()) removal(valueEnd(all[keptEnd - 1].offset()), valueEnd(all.back().offset()));
        }
    }

    // An array of an object's member that loses every item goes whole, its key with it
    // ("primitives": [] says nothing); so, in turn, may the object's own array.
    void emptiedArraysGo() {
        for (bool again = true; again;) {
            again = false;
            for (auto it = removed_.begin(); it != removed_.end(); ++it) {
                const JsonValue container = src_.tree.at(it->first);
                if (!container.isArray() || it->second.size() != container.size() || it->first == 0 ||
                    growing_.count(it->first))
                    continue;
                const JsonValue parent = parentOf(container);
                if (!parent.isObject() || parent.index() == 0) continue;
                removed_[parent.index()].insert(container.index());
                removed_.erase(it);
                again = true;
                break;
            }
        }
    }

    void removal(size_t begin, size_t end) {
        removals_.emplace_back(begin, end);
        splices_.push_back({begin, end, ""});
    }

    // What lies inside a removed range goes with it.
    std::vector<Splice> withoutNested() const {
        std::vector<Splice> kept;
        for (const Splice& s : splices_) {
            const bool inside = std::any_of(removals_.begin(), removals_.end(), [&](const auto& r) {
                if (s.begin == r.first && s.end == r.second && s.text.empty()) return false;  // itself
                if (s.begin == s.end) return s.begin > r.first && s.begin < r.second;
                return s.begin >= r.first && s.end <= r.second;
            });
            if (!inside) kept.push_back(s);
        }
        return kept;
    }

    const SceneDocument& doc_;
    const JsonSource& src_;
    const SceneDocument& was_;
    const Resources& resources_;
    const fs::path target_;
    FileReferences references_;
    std::optional<JsonWriter> writer_;  // made when something new is written
    Index now_, then_;
    std::vector<Splice> splices_;
    std::map<uint32_t, std::set<uint32_t>> removed_;  // by container: the items it loses
    std::set<SourceId> claimed_;                       // the values a node is compared with in place
    std::map<std::pair<uint32_t, std::string>, std::unique_ptr<NewItems>> pending_;  // by holder and key
    std::set<uint32_t> growing_;                       // arrays that gain items
    std::vector<std::pair<size_t, size_t>> removals_;
};

}  // namespace

std::vector<Splice> jsonDocumentSplices(const SceneDocument& document, const Resources& resources,
                                        const fs::path& target) {
    try {
        return JsonSplicer(document, resources, target).splices();
    } catch (const Unsaveable& why) {
        throw InputError(document.file.string() + ": error: the scene is not saved, the file is kept as it was: " +
                         why.what + "; " + why.remedy);
    }
}

void placeLightsByTheirGroups(const SceneDocument& before, SceneDocument& after) {
    if (!after.jsonSource || before.lights.size() != after.lights.size() || after.lightSources.size() != after.lights.size())
        return;  // an edit of the lights themselves: they are as it left them
    const JsonSource& source = *after.jsonSource;
    const LightPlacements was(before, source), now(after, source);
    for (const auto& [light, frames] : was.all()) {
        const std::vector<Affine>& moved = now.of(light);
        if (moved.size() == frames.size() &&
            std::equal(moved.begin(), moved.end(), frames.begin(),
                       [](const Affine& a, const Affine& b) { return std::memcmp(&a, &b, sizeof a) == 0; }))
            continue;
        std::vector<size_t> places;  // the light's, in order
        for (size_t i = 0; i < after.lights.size(); ++i)
            if (after.lightSources[i] == light) places.push_back(i);
        // Only lights as their groups put them follow them: one set on its own stays (the save
        // writes it, or refuses what the file cannot say).
        bool asPlaced = places.size() == frames.size();
        for (size_t k = 0; asPlaced && k < places.size(); ++k)
            asPlaced = sameLight(after.lights[places[k]], placedLight(source, light, frames[k]));
        if (!asPlaced) continue;
        if (moved.size() == places.size()) {
            for (size_t k = 0; k < places.size(); ++k) after.lights[places[k]] = placedLight(source, light, moved[k]);
            continue;
        }
        // Placed more or fewer times (a placement duplicated or deleted, a group removed): the
        // light's places are made again where the first was.
        const size_t at = places.empty() ? after.lights.size() : places.front();
        std::vector<int> ids;
        for (auto k = places.rbegin(); k != places.rend(); ++k) {
            ids.insert(ids.begin(), after.lightIds[*k]);
            after.lights.erase(after.lights.begin() + std::ptrdiff_t(*k));
            after.lightSources.erase(after.lightSources.begin() + std::ptrdiff_t(*k));
            after.lightIds.erase(after.lightIds.begin() + std::ptrdiff_t(*k));
        }
        for (size_t k = 0; k < moved.size(); ++k) {
            const auto offset = std::ptrdiff_t(at + k);
            after.lights.insert(after.lights.begin() + offset, placedLight(source, light, moved[k]));
            after.lightSources.insert(after.lightSources.begin() + offset, light);
            after.lightIds.insert(after.lightIds.begin() + offset, k < ids.size() ? ids[k] : after.nextNodeId++);
        }
    }
}

std::optional<std::string> jsonUnsaveable(const SceneDocument& document, const Resources& resources) {
    if (!document.jsonSource) return std::nullopt;
    try {
        JsonSplicer(document, resources, document.file).splices();
    } catch (const Unsaveable& why) {
        return why.what + "; " + why.remedy;
    } catch (const InputError& e) {  // a texture or mesh made in memory
        return std::string(e.what());
    }
    return std::nullopt;
}

}  // namespace ray
