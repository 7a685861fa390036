// The XML tree of a plain scene text, read in one pass over the text without expat.
//
// A large flat scene (10^5 spheres: 31 MB, a million elements) spent most of its load in
// expat's tokenizer, which checks every byte against an encoding's tables and hands each
// element over as copied strings. Scene files are nearly always plain: ASCII elements and
// attributes, blanks and comments between them. This reader takes exactly that subset and
// builds the same XmlTree (names, attributes, lines, spans) as expat would, scanning each
// byte once and copying only the values into the tree.
//
// Whatever lies outside the subset, or is wrong, it does not judge: it gives nullopt and
// expat reads the text from the start (XmlTree::parse does), so that every error keeps
// expat's words and line, and every construct it knows (entities, CDATA, DOCTYPE, other
// encodings) keeps its meaning. The subset:
// - an optional UTF-8 byte-order mark, and an optional <?xml ...?> declaration of version
//   1.0 with an optional UTF-8 encoding and standalone;
// - elements with ASCII names ([A-Za-z_][A-Za-z0-9._-]*), attributes quoted with ' or ",
//   written once each, values without '<', '&' or a carriage return;
// - between tags: blanks, text without '&' or "]]>", comments ("--" inside taken, as the
//   loader takes it: xml_tree.cpp);
// - only ASCII bytes, no control character but tab, line feed and carriage return;
// - elements nested at most maxDepth deep; what follows the root's end tag is ignored.
#pragma once

#include <optional>
#include <string_view>

#include "scene/xml_tree.h"

namespace ray {

// The tree of `text` when it is plain XML as above, with each element's span when
// `recordSpans`; nullopt otherwise.
std::optional<XmlTree> readPlainXml(std::string_view text, int maxDepth, bool recordSpans);
// The same from what `source` gives, read a piece at a time (`expectedBytes`, the size when
// known, sizes the tree's arrays): the text is never held whole. On nullopt the caller
// reads the text again from its start for expat (the source is read part of the way).
std::optional<XmlTree> readPlainXml(const XmlSource& source, size_t expectedBytes, int maxDepth, bool recordSpans);

}  // namespace ray
