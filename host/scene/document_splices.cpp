// The splices a save makes in a file's text (document_splices.h).
#include "scene/document_splices.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <span>

#include "scene/canonical_writer.h"
#include "scene/document_fields.h"
#include "scene/value_text.h"

namespace fs = std::filesystem;

namespace ray {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

std::optional<TransformKind> transformKindOf(const char* name) {
    if (sameName(name, "translate")) return TransformKind::Translate;
    if (sameName(name, "rotate")) return TransformKind::Rotate;
    if (sameName(name, "scale")) return TransformKind::Scale;
    if (sameName(name, "matrix")) return TransformKind::Matrix;
    return std::nullopt;
}

bool isObject(const char* name) { return sameName(name, "object"); }
bool isBlockElement(const char* name) { return sameName(name, "transblock") || sameName(name, "object"); }

SourceId itemSource(const SceneItem& item) {
    if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) return primitive->source;
    if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) return (*subtree)->source;
    if (const auto* master = std::get_if<MasterReference>(&item)) return master->source;
    return std::get<Box<CsgNode>>(item)->source;
}

// A block the file writes as its one object, bare in a tree or a csg, and still can.
bool writtenBare(const Block& block) {
    return block.source == kNoSource && block.bare && block.transforms.empty() && block.motion == Vec3{} &&
           block.items.size() == 1;
}

class SpliceWriter {
public:
    SpliceWriter(const SceneDocument& document, const Resources& resources, const fs::path& target)
        : document_(document), source_(*document.source), bytes_(source_.bytes()), resources_(resources),
          canonical_(document, resources, target, TextStyle{source_.newline(), source_.indentUnit()}),
          claimed_(source_.elementCount(), false), keptInPlace_(source_.elementCount(), false) {
        sameFolder_ = canonical_.references().sameFolderAs(document.file);
        canonical_.keptItem = [this](const SceneItem& item, const std::string& indent) {
            return moved(itemSource(item), indent, [&] { itemInPlace(item); });
        };
        canonical_.keptBlock = [this](const Block& block, const std::string& indent) -> std::optional<std::string> {
            if (block.source == kNoSource) return std::nullopt;
            return moved(block.source, indent, [&] { blockInPlace(block); });
        };
    }

    std::vector<Splice> splices() {
        claimed_[kRoot] = true;
        writeGlobals();
        writeCamera();
        const size_t afterLights = writeLights();
        writeTrees(afterLights);
        finish(sink_);
        return std::move(sink_.splices);
    }

private:
    static constexpr SourceId kRoot = 0;

    // Where splices go: the save's, or those of one element whose text moves.
    struct Sink {
        std::vector<Splice> splices;
        std::map<SourceId, std::string> intoSelfClosing;  // children for <a/>, which must open
    };

    // A child of a container as the document has it: the element it keeps (kNoSource: none),
    // how to edit that element in place, and its text for anywhere else.
    struct Child {
        SourceId element = kNoSource;
        std::function<void()> inPlace;
        std::function<std::string(const std::string& indent)> text;
    };

    // ---- the text's elements

    std::vector<SourceId> children(SourceId parent) const {
        std::vector<SourceId> ids;
        for (XmlElement c = source_.element(parent).firstChild(); c; c = c.nextSibling()) ids.push_back(c.index());
        return ids;
    }

    // The last child named `name` (the one the loader's value comes from), among those of
    // every element of `parents`.
    SourceId lastNamed(std::span<const SourceId> parents, const char* name) const {
        SourceId found = kNoSource;
        for (SourceId parent : parents)
            for (XmlElement c = source_.element(parent).firstChild(); c; c = c.nextSibling())
                if (sameName(c.name(), name)) found = c.index();
        return found;
    }
    SourceId lastNamed(SourceId parent, const char* name) const { return lastNamed(std::span(&parent, 1), name); }

    std::vector<SourceId> rootChildrenNamed(const char* name) const {
        std::vector<SourceId> ids;
        for (SourceId c : children(kRoot))
            if (sameName(source_.element(c).name(), name)) ids.push_back(c);
        return ids;
    }

    size_t end(SourceId id) const { return size_t(source_.span(id).end); }
    size_t startTagEnd(SourceId id) const { return size_t(source_.span(id).startTagEnd); }
    // Where a child goes after the others: the last child's end, or the start tag's.
    size_t afterChildren(SourceId parent) const {
        const std::vector<SourceId> all = children(parent);
        return all.empty() ? startTagEnd(parent) : end(all.back());
    }

    // The indentation of a new child: its siblings', or one step more than its parent's.
    std::string childIndent(SourceId parent) const {
        for (SourceId c : children(parent))
            if (auto indent = source_.indentation(c)) return std::string(*indent);
        return std::string(source_.indentation(parent).value_or("")) + source_.indentUnit();
    }

    // ---- splices

    void replace(size_t begin, size_t end, std::string text) { sink_.splices.push_back({begin, end, std::move(text)}); }

    void remove(SourceId id) {
        const auto [begin, end] = source_.removalRange(id);
        replace(begin, end, "");
    }

    // A child element, on a line of its own at `indent`, at `at` (just after a sibling, or
    // the parent's start tag).
    void insertChild(SourceId parent, size_t at, const std::string& indent, const std::string& text) {
        const std::string line = source_.newline() + indent + text;
        if (source_.selfClosing(parent) && at == end(parent))
            sink_.intoSelfClosing[parent] += line;
        else
            replace(at, at, line);
    }

    void appendChild(SourceId parent, const std::string& text) {
        insertChild(parent, afterChildren(parent), childIndent(parent), text);
    }

    // <a/> given children becomes <a>children</a>.
    void finish(Sink& sink) const {
        for (const auto& [parent, content] : sink.intoSelfClosing) {
            const std::string indent(source_.indentation(parent).value_or(""));
            const size_t close = end(parent) - 2;  // "/>"
            sink.splices.push_back({close, end(parent),
                                    ">" + content + source_.newline() + indent + "</" +
                                        source_.element(parent).name() + ">"});
        }
        sink.intoSelfClosing.clear();
    }

    // The text of element `id`, its own edits (made by `inPlace`) applied, indented at
    // `indent` (for an element that moves); nullopt when it is written already.
    std::optional<std::string> moved(SourceId id, const std::string& indent, const std::function<void()>& inPlace) {
        if (id == kNoSource || claimed_[id]) return std::nullopt;
        claimed_[id] = true;
        Sink outer = std::move(sink_);
        sink_ = Sink();
        inPlace();
        finish(sink_);
        Sink own = std::move(sink_);
        sink_ = std::move(outer);
        const size_t begin = size_t(source_.span(id).begin);
        for (Splice& s : own.splices) s.begin -= begin, s.end -= begin;
        const std::string text =
            applySplices(std::string_view(bytes_).substr(begin, end(id) - begin), std::move(own.splices));
        return reindented(text, std::string(source_.indentation(id).value_or("")), indent);
    }

    static std::string reindented(const std::string& text, const std::string& from, const std::string& to) {
        std::string out;
        size_t at = 0;
        for (size_t newline; (newline = text.find('\n', at)) != std::string::npos; at = newline + 1) {
            out.append(text, at, newline + 1 - at);
            if (text.compare(newline + 1, from.size(), from) == 0) {
                out += to;
                newline += from.size();
            }
        }
        return out + text.substr(at);
    }

    // Sets attribute `i` of element `id` to `text` (escaped), inside its quotes.
    void setAttribute(SourceId id, size_t i, const std::string& text) {
        const SourceText::Attribute a = source_.attributes(id).at(i);
        std::string value = text;
        if (a.quote == '\'') {  // escapedAttribute quotes for '"'
            std::string quoted;
            for (char c : value) quoted += c == '\'' ? std::string("&apos;") : std::string(1, c);
            value = quoted;
        }
        replace(a.valueBegin, a.valueEnd, value);
    }

    void appendAttribute(SourceId id, const char* name, const std::string& text) {
        const size_t at = source_.attributeInsertion(id);
        replace(at, at, std::string(" ") + name + "=\"" + text + "\"");
    }

    // Numbers `values` in the attributes of `id` from `first` on; a value whose attribute
    // is missing is added under `names` when it differs from `defaults` (or any after it does).
    void numbers(SourceId id, size_t first, std::span<const double> values, std::span<const char* const> names,
                 const std::string& owner, const std::string& field, std::span<const double> defaults = {}) {
        const XmlElement element = source_.element(id);
        size_t needed = values.size();
        if (!defaults.empty())
            while (needed > 0 && first + needed > element.attributeCount() &&
                   sameBits(values[needed - 1], defaults[needed - 1]))
                --needed;
        for (size_t k = 0; k < needed; ++k) {
            const std::string text = canonical_.number(numberKey(owner, field, k), values[k]);
            const size_t i = first + k;
            if (i >= element.attributeCount())
                appendAttribute(id, names[k], text);
            else if (!sameBits(readNumber(element.attributeValue(i)).value, values[k]))
                setAttribute(id, i, text);
        }
    }

    void triple(SourceId id, const Vec3& v, const std::array<const char*, 3>& names, const std::string& owner,
                const char* field) {
        const double values[] = {v.x, v.y, v.z};
        numbers(id, 0, values, names, owner, field);
    }

    void single(SourceId id, double v, const std::string& owner, const char* field) {
        static const char* const kV[] = {"v"};
        numbers(id, 0, std::span(&v, 1), kV, owner, field);
    }

    // Fields of a table, each written in the last element of its name among `parents`,
    // or added to the last of them when it differs from `defaults`'s.
    template <class Owner, class Fields, class Element>
    void tripleFields(std::span<const SourceId> parents, const Owner& value, const Owner& defaults,
                      const Fields& fields, const std::string& owner, const Element& element) {
        for (const auto& field : fields) {
            if (SourceId id = lastNamed(parents, field.element); id != kNoSource)
                triple(id, value.*field.member, field.attributes, owner, field.element);
            else if (value.*field.member != defaults.*field.member)
                appendChild(parents.back(), element(field.element));
        }
    }

    template <class Owner, class Fields, class Element>
    void singleFields(std::span<const SourceId> parents, const Owner& value, const Owner& defaults,
                      const Fields& fields, const std::string& owner, const Element& element) {
        for (const auto& field : fields) {
            if (SourceId id = lastNamed(parents, field.element); id != kNoSource)
                single(id, value.*field.member, owner, field.element);
            else if (value.*field.member != defaults.*field.member)
                appendChild(parents.back(), element(field.element));
        }
    }

    // ---- children

    // The document's `wanted` children of `parent`, against the file's children for which
    // `modeled` holds: those still in order are edited in place, the others removed, and
    // the new or moved written after the child before them (or at `fallback`). Returns
    // where a next child would go.
    size_t writeChildren(SourceId parent, bool (*modeled)(const char*), std::vector<Child>& wanted, size_t fallback) {
        SourceId last = 0;
        bool any = false;
        for (Child& c : wanted) {
            const bool keep = c.element != kNoSource && source_.parent(c.element) == parent && !claimed_[c.element] &&
                              (!any || c.element > last);
            if (!keep) {
                c.element = kNoSource;
                continue;
            }
            claimed_[c.element] = true;
            keptInPlace_[c.element] = true;
            last = c.element;
            any = true;
        }
        for (SourceId c : children(parent))
            if (modeled(source_.element(c).name()) && !keptInPlace_[c]) remove(c);
        const std::string indent = childIndent(parent);
        size_t at = fallback;
        for (Child& c : wanted) {
            if (c.element != kNoSource) {
                c.inPlace();
                at = end(c.element);
            } else {
                insertChild(parent, at, indent, c.text(indent));
            }
        }
        return at;
    }

    // ---- globals, camera, lights

    void writeGlobals() {
        const std::vector<SourceId> elements = rootChildrenNamed("globaldata");
        const GlobalCoefficients defaults;
        if (elements.empty()) {
            const GlobalCoefficients& g = document_.globals;
            if (g.ka != defaults.ka || g.kd != defaults.kd || g.ks != defaults.ks || g.kt != defaults.kt)
                insertChild(kRoot, startTagEnd(kRoot), childIndent(kRoot), canonical_.globals(childIndent(kRoot)));
            return;
        }
        singleFields(std::span<const SourceId>(elements), document_.globals, defaults,
                     kGlobalsSingles, "globals",
                     [&](const char* name) { return canonical_.globalsElement(name); });
    }

    void writeCamera() {
        const std::vector<SourceId> elements = rootChildrenNamed("cameradata");
        const Camera& camera = document_.camera;
        const Camera defaults;
        if (elements.empty()) {
            if (!(camera == defaults)) {
                const std::vector<SourceId> globals = rootChildrenNamed("globaldata");
                const size_t at = globals.empty() ? startTagEnd(kRoot) : end(globals.back());
                insertChild(kRoot, at, childIndent(kRoot), canonical_.camera(childIndent(kRoot)));
            }
            return;
        }
        const std::span<const SourceId> parents(elements);
        auto element = [&](const char* name) { return canonical_.cameraElement(name); };
        const TripleField<Camera> position[] = {kCameraTriples[0]}, up[] = {kCameraTriples[2]};
        const SourceId positionElement = lastNamed(parents, "pos");
        const Vec3 writtenPosition = positionElement == kNoSource ? defaults.position : readTriple(positionElement);
        tripleFields(parents, camera, defaults, position, "camera", element);
        writeLook(parents, writtenPosition);
        tripleFields(parents, camera, defaults, up, "camera", element);
        singleFields(parents, camera, defaults, kCameraSingles, "camera", element);
    }

    Vec3 readTriple(SourceId id) const {
        const XmlElement e = source_.element(id);
        auto at = [&](size_t i) { return i < e.attributeCount() ? readNumber(e.attributeValue(i)).value : 0.0; };
        return {at(0), at(1), at(2)};
    }

    // <look> is the direction; a <focus> point (look = focus - pos) stays a focus point
    // when the point reads back as the direction the camera has.
    void writeLook(std::span<const SourceId> parents, const Vec3& writtenPosition) {
        SourceId look = kNoSource;
        for (SourceId parent : parents)
            for (SourceId c : children(parent))
                if (sameName(source_.element(c).name(), "look") || sameName(source_.element(c).name(), "focus")) look = c;
        const Camera& camera = document_.camera;
        if (look == kNoSource) {
            if (camera.look != Camera().look) appendChild(parents.back(), canonical_.cameraElement("look"));
            return;
        }
        if (sameName(source_.element(look).name(), "look")) {
            triple(look, camera.look, kXyz, "camera", "look");
            return;
        }
        const Vec3 focus = readTriple(look);
        if (sameBits(camera.position, writtenPosition) && sameBits(focus - writtenPosition, camera.look)) return;
        const Vec3 newFocus = camera.position + camera.look;
        if (sameBits(newFocus - camera.position, camera.look))
            triple(look, newFocus, kXyz, "camera", "focus");
        else  // no point reads back as this direction: the direction it is
            replace(size_t(source_.span(look).begin), end(look), canonical_.cameraElement("look"));
    }

    size_t writeLights() {
        std::vector<Child> wanted;
        for (size_t i = 0; i < document_.lights.size(); ++i) {
            const SourceId element = i < document_.lightSources.size() ? document_.lightSources[i] : kNoSource;
            wanted.push_back({element, [this, i, element] { lightInPlace(i, element); },
                              [this, i](const std::string& indent) { return canonical_.light(i, indent); }});
        }
        std::vector<SourceId> before = rootChildrenNamed("cameradata");
        for (SourceId g : rootChildrenNamed("globaldata")) before.push_back(g);
        size_t fallback = startTagEnd(kRoot);
        for (SourceId b : before) fallback = std::max(fallback, end(b));
        return writeChildren(kRoot, [](const char* name) { return sameName(name, "lightdata"); }, wanted, fallback);
    }

    void lightInPlace(size_t index, SourceId id) {
        const Light& light = document_.lights[index];
        const Light defaults;
        const std::string owner = "light " + std::to_string(index);
        auto element = [&](const char* name) { return canonical_.lightElement(index, name); };
        const SourceId type = lastNamed(id, "type");
        if (type == kNoSource) {
            if (light.type != defaults.type) appendChild(id, element("type"));
        } else if (!sameName(source_.element(type).attributeValue(0), lightTypeName(light.type))) {
            setAttribute(type, 0, lightTypeName(light.type));
        }
        tripleFields(std::span<const SourceId>(&id, 1), light, defaults, kLightTriples, owner, element);
        singleFields(std::span<const SourceId>(&id, 1), light, defaults, kLightSingles, owner, element);
    }

    // ---- trees, blocks, objects

    void writeTrees(size_t fallback) {
        std::vector<Child> wanted;
        for (NamedTree* tree : treesInOrder(const_cast<SceneDocument&>(document_))) {
            const NamedTree& named = *tree;
            wanted.push_back({named.tree.source, [this, &named] { namedTreeInPlace(named); },
                              [this, &named](const std::string& indent) { return canonical_.namedTree(named, indent); }});
        }
        writeChildren(kRoot, isObject, wanted, fallback);
    }

    void namedTreeInPlace(const NamedTree& named) {
        const SourceId id = named.tree.source;
        const XmlElement e = source_.element(id);
        if (e.attributeCount() > 1 && named.name != e.attributeValue(1))
            setAttribute(id, 1, escapedAttribute(named.name, "tree name"));
        blocksInPlace(id, named.tree.blocks);
    }

    Child blockChild(const Block& block) {
        if (writtenBare(block)) {
            const SceneItem& item = block.items.front();
            return {itemSource(item), [this, &item] { itemInPlace(item); },
                    [this, &item](const std::string& indent) { return canonical_.item(item, indent); }};
        }
        return {block.source, [this, &block] { blockInPlace(block); },
                [this, &block](const std::string& indent) { return canonical_.block(block, indent); }};
    }

    void blocksInPlace(SourceId parent, const std::vector<Block>& blocks) {
        std::vector<Child> wanted;
        for (const Block& block : blocks) wanted.push_back(blockChild(block));
        writeChildren(parent, isBlockElement, wanted, startTagEnd(parent));
    }

    void blockInPlace(const Block& block) {
        const SourceId id = block.source;
        const size_t afterTransforms = transformsInPlace(block);
        const size_t afterMotion = motionInPlace(block, afterTransforms);
        std::vector<Child> wanted;
        for (const SceneItem& item : block.items)
            wanted.push_back({itemSource(item), [this, &item] { itemInPlace(item); },
                              [this, &item](const std::string& indent) { return canonical_.item(item, indent); }});
        writeChildren(id, isObject, wanted, afterMotion);
    }

    // The block's transforms against the file's, in order: one of the same kind at the same
    // place is edited, the rest removed or added. Returns where the next would go.
    size_t transformsInPlace(const Block& block) {
        const SourceId id = block.source;
        std::vector<SourceId> written;
        for (SourceId c : children(id))
            if (transformKindOf(source_.element(c).name())) written.push_back(c);
        const std::string indent = childIndent(id);
        size_t at = startTagEnd(id);
        for (size_t i = 0; i < std::max(written.size(), block.transforms.size()); ++i) {
            const bool same = i < written.size() && i < block.transforms.size() &&
                              transformKindOf(source_.element(written[i]).name()) == block.transforms[i].kind;
            if (same) {
                transformInPlace(block, i, written[i]);
                at = end(written[i]);
                continue;
            }
            if (i < written.size()) remove(written[i]);
            if (i < block.transforms.size()) insertChild(id, at, indent, canonical_.transform(block, i, indent));
        }
        return at;
    }

    void transformInPlace(const Block& block, size_t index, SourceId id) {
        const TransformOp& op = block.transforms[index];
        const std::string owner = "block " + std::to_string(block.id), field = "transform " + std::to_string(index);
        static const char* const kNames[] = {"x", "y", "z", "angle"};
        if (op.kind != TransformKind::Matrix) {
            numbers(id, 0, std::span(op.v.data(), op.kind == TransformKind::Rotate ? 4 : 3), kNames, owner, field);
            return;
        }
        const std::vector<SourceId> rows = children(id);
        for (size_t r = 0; r < 3 && r < rows.size(); ++r)
            for (size_t c = 0; c < 4; ++c) {
                // The keys number a matrix's values row by row (numberKey's index).
                const std::string text = canonical_.number(numberKey(owner, field, 4 * r + c), op.v[4 * r + c]);
                const XmlElement row = source_.element(rows[r]);
                if (c < row.attributeCount() && !sameBits(readNumber(row.attributeValue(c)).value, op.v[4 * r + c]))
                    setAttribute(rows[r], c, text);
            }
    }

    // <motion>s add up (the loader's rule): the first takes the block's motion when they no
    // longer do, and the others go.
    size_t motionInPlace(const Block& block, size_t at) {
        const SourceId id = block.source;
        std::vector<SourceId> written;
        Vec3 sum;
        for (SourceId c : children(id))
            if (sameName(source_.element(c).name(), "motion")) {
                written.push_back(c);
                sum += readTriple(c);
            }
        if (written.empty()) {
            if (block.motion != Vec3{}) insertChild(id, at, childIndent(id), canonical_.motion(block));
            return at;
        }
        if (sameBits(sum, block.motion)) return at;
        triple(written.front(), block.motion, kXyz, "block " + std::to_string(block.id), "motion");
        for (size_t i = 1; i < written.size(); ++i) remove(written[i]);
        return at;
    }

    void itemInPlace(const SceneItem& item) {
        if (const auto* primitive = std::get_if<PrimitiveNode>(&item)) return primitiveInPlace(*primitive);
        if (const auto* subtree = std::get_if<Box<TreeNode>>(&item)) {
            return blocksInPlace((*subtree)->source, (*subtree)->blocks);
        }
        if (const auto* master = std::get_if<MasterReference>(&item)) {
            const XmlElement e = source_.element(master->source);
            if (e.attributeCount() > 1 && master->name != e.attributeValue(1))
                setAttribute(master->source, 1, escapedAttribute(master->name, "master name"));
            return;
        }
        const CsgNode& csg = *std::get<Box<CsgNode>>(item);
        csgInPlace(csg);
    }

    void csgInPlace(const CsgNode& csg) {
        static const char* const kOperations[] = {"union", "intersection", "difference"};
        const char* operation = csg.operation == CsgStepKind::Intersection ? kOperations[1]
                                : csg.operation == CsgStepKind::Difference ? kOperations[2]
                                                                            : kOperations[0];
        const XmlElement e = source_.element(csg.source);
        if (e.attributeCount() > 1 && !sameName(e.attributeValue(1), operation)) setAttribute(csg.source, 1, operation);
        std::vector<Child> wanted;
        for (const TreeNode& operand : csg.operands) {
            if (operand.blocks.size() == 1) {
                wanted.push_back(blockChild(operand.blocks.front()));
                continue;
            }
            wanted.push_back({kNoSource, [] {},
                              [this, &operand](const std::string& indent) { return canonical_.operand(operand, indent); }});
        }
        writeChildren(csg.source, isBlockElement, wanted, startTagEnd(csg.source));
    }

    void primitiveInPlace(const PrimitiveNode& node) {
        const SourceId id = node.source;
        const XmlElement e = source_.element(id);
        if (e.attributeCount() > 1 && !sameName(e.attributeValue(1), primitiveTypeName(node.type)))
            setAttribute(id, 1, primitiveTypeName(node.type));
        if (node.type == PrimitiveType::Mesh) {
            const bool asWritten = node.files && !node.files->meshWritten.empty() && sameFolder_ &&
                                   e.attributeCount() > 2 && node.files->meshWritten == e.attributeValue(2);
            const std::string file = meshFileOf(node, resources_, canonical_.references());
            if (!asWritten && (e.attributeCount() <= 2 || file != e.attributeValue(2))) {
                if (e.attributeCount() > 2) setAttribute(id, 2, escapedAttribute(file, "mesh file"));
                else appendAttribute(id, "meshfile", escapedAttribute(file, "mesh file"));
            }
        }
        const std::string owner = "object " + std::to_string(node.id);
        auto element = [&](const char* name) { return canonical_.materialElement(node, name); };
        const Material defaults;
        tripleFields(std::span<const SourceId>(&id, 1), node.material, defaults, kMaterialTriples, owner, element);
        singleFields(std::span<const SourceId>(&id, 1), node.material, defaults, kMaterialSingles, owner, element);
        mapInPlace(node, false);
        mapInPlace(node, true);
    }

    // <texture file u v> or <bumpmap ...>: the file as written while it names the same one.
    void mapInPlace(const PrimitiveNode& node, bool bumpMap) {
        const char* name = bumpMap ? "bumpmap" : "texture";
        const SourceId id = lastNamed(node.source, name);
        const std::string file = imageFileOf(node, bumpMap, resources_, canonical_.references());
        if (id == kNoSource) {
            if (!file.empty()) appendChild(node.source, canonical_.mapElement(node, bumpMap));
            return;
        }
        const XmlElement e = source_.element(id);
        const std::string written = e.attributeCount() > 0 ? e.attributeValue(0) : "";
        if (file.empty() && written.find_first_not_of(" \t\r\n") != std::string::npos) {
            remove(id);  // the document names none now
            return;
        }
        if (!file.empty() && !namesAsWritten(node, bumpMap, written) && file != written)
            setAttribute(id, 0, escapedAttribute(file, bumpMap ? "bump map file" : "texture file"));
        const TextureMap& map = bumpMap ? node.material.bumpMap : node.material.texture;
        const double repeats[] = {map.repeatU, map.repeatV}, defaults[] = {1, 1};
        static const char* const kNames[] = {"u", "v"};
        numbers(id, 1, repeats, kNames, "object " + std::to_string(node.id), name, defaults);
    }

    // Whether the node names the file the element writes, as the element writes it (a
    // file not found keeps its name; a found one its name while saved beside the original).
    bool namesAsWritten(const PrimitiveNode& node, bool bumpMap, const std::string& written) const {
        if (!node.files) return false;
        const std::optional<ImageReference>& file = bumpMap ? node.files->bumpMap : node.files->texture;
        const std::string& missing = bumpMap ? node.files->missingBumpMap : node.files->missingTexture;
        if (file) return sameFolder_ && !file->written.empty() && file->written == written;
        return !missing.empty() && missing == written;
    }

    const SceneDocument& document_;
    const SourceText& source_;
    const std::string& bytes_;
    const Resources& resources_;
    CanonicalWriter canonical_;
    std::vector<bool> claimed_;      // elements whose text is written (in place, or moved)
    std::vector<bool> keptInPlace_;  // of those, the ones written where they are
    Sink sink_;
    bool sameFolder_ = true;
};

}  // namespace

std::vector<Splice> documentSplices(const SceneDocument& document, const Resources& resources, const fs::path& target) {
    return SpliceWriter(document, resources, target).splices();
}

}  // namespace ray
