// What a save changes in a file's text: the splices (source_text.h) that make the text of a
// document read from a file say what the document says now.
//
// The document is the truth and the text its record: edits change the document alone, and
// the save compares each node with the element it was read from. What reads as the node
// holds stays byte for byte; a number that differs is written over the old one's text,
// inside its quotes (as the user typed it, or in the shortest form that reads back as it:
// SceneDocument::typedNumbers); a field the element lacks is added as a line like its
// siblings; an element no node claims (removed) goes with its own lines; a node with no
// element (added) is written canonically (canonical_writer.h) where the document puts it,
// indented like its neighbours; an element whose node moved (into a new transblock, say)
// is taken out of its old place and its text, with its own edits, written at the new one.
// Every kind of element the document models is covered; elements it does not (comments,
// <aspectratio>, a light's <id>, unknown ones) are kept as they are.
#pragma once

#include <filesystem>
#include <vector>

#include "scene/scene_document.h"
#include "scene/source_text.h"

namespace ray {

// The splices for `document`, whose source must be set and splicable
// (SourceText::canSplice). Paths are written as FileReferences of `target` says.
// Throws InputError for what a file cannot hold (a texture or mesh made in memory).
std::vector<Splice> documentSplices(const SceneDocument& document, const Resources& resources,
                                    const std::filesystem::path& target);

}  // namespace ray
