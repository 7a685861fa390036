// The canonical text of a scene document (SPEC §1): every element on a line of its own,
// indented a step a level, numbers in the shortest form that reads back as the same
// double. It writes a document made in code whole, and each element an edit adds to a
// file that keeps its text (document_splices.h), indented as the file indents.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "scene/scene_document.h"

namespace ray {

// How new text is laid out: the line break and one step of indentation.
struct TextStyle {
    std::string newline = "\n";
    std::string indentUnit = "  ";
};

// The text of `file` as the saved file names it: relative to the folder it is saved in.
class FileReferences {
public:
    explicit FileReferences(const std::filesystem::path& target);
    std::string relative(const std::filesystem::path& file) const;  // not escaped
    // Whether the saved file is in `documentFile`'s folder, where what it names as written
    // still names the same files.
    bool sameFolderAs(const std::filesystem::path& documentFile) const;

private:
    std::filesystem::path folder_;
};

// A value as XML writes it in an attribute between double quotes. Throws InputError, naming
// `what` the value is ("tree name", "texture file"), for text XML cannot hold
// (xml_characters.h).
std::string escapedAttribute(const std::string& text, std::string_view what);

// What a primitive's texture or bump map names, unescaped: the file's reference as it
// was resolved, as written when it was not found, an image loaded from a file in code;
// empty for none. Throws InputError for an image made in memory.
std::string imageFileOf(const PrimitiveNode& node, bool bumpMap, const Resources& resources,
                        const FileReferences& references);
// What a mesh primitive names (its OBJ file), unescaped. Throws InputError for a mesh
// made in memory.
std::string meshFileOf(const PrimitiveNode& node, const Resources& resources, const FileReferences& references);

class CanonicalWriter {
public:
    CanonicalWriter(const SceneDocument& document, const Resources& resources, const std::filesystem::path& target,
                    TextStyle style = {});

    // An element that keeps its file's text instead (document_splices.h): given a node and
    // the indentation of its first line, its text, or nullopt to write it here.
    std::function<std::optional<std::string>(const SceneItem&, const std::string& indent)> keptItem;
    std::function<std::optional<std::string>(const Block&, const std::string& indent)> keptBlock;

    // The whole document, with a line break at its end.
    std::string document();

    // One element as it would be written at `indent`: its first line not indented (the
    // caller places it), the next ones indented from `indent`, no line break at the end.
    std::string globals(const std::string& indent);
    std::string camera(const std::string& indent);
    std::string light(size_t index, const std::string& indent);
    std::string namedTree(const NamedTree& tree, const std::string& indent);
    std::string block(const Block& block, const std::string& indent);
    std::string item(const SceneItem& item, const std::string& indent);
    // A csg operand: its block, or a block holding its blocks as an inline tree.
    std::string operand(const TreeNode& operand, const std::string& indent);
    std::string transform(const Block& block, size_t index, const std::string& indent);
    std::string motion(const Block& block);
    // <diffuse r="" g="" b=""/> and the like, of object `id`'s material (one line).
    std::string materialElement(const PrimitiveNode& node, const char* element);
    // <texture file="" u="" v=""/> (or bumpmap); empty when the node names none.
    std::string mapElement(const PrimitiveNode& node, bool bumpMap);
    std::string lightElement(size_t index, const char* element);
    std::string cameraElement(const char* element);
    std::string globalsElement(const char* element);

    // A number of the document as a save writes it (SceneDocument::typedNumbers).
    std::string number(const std::string& key, double value) const;
    const FileReferences& references() const { return references_; }
    const TextStyle& style() const { return style_; }

private:
    template <class Owner, class Field>
    std::string tripleElement(const Owner& owner, const Field& field, const std::string& key);
    std::string indented(const std::string& indent, int depth) const;
    std::string primitive(const PrimitiveNode& node, const std::string& indent);
    std::string csg(const CsgNode& csg, const std::string& indent);
    std::string tree(const TreeNode& tree, const char* open, const std::string& indent);

    const SceneDocument& document_;
    const Resources& resources_;
    FileReferences references_;
    TextStyle style_;
};

}  // namespace ray
