// A text handed to the XML readers a piece at a time, as a file's reads hand it over: the
// tests of the XML tree and of the plain-XML reader feed it so to cross every boundary.
#pragma once

#include <algorithm>
#include <cstring>
#include <string>

#include "scene/xml_tree.h"

namespace ray::test {

// `xml` handed over `piece` bytes at a time (the source reads `xml`, which must outlive it).
inline XmlSource xmlInPieces(const std::string& xml, size_t piece) {
    return [&xml, piece, at = size_t(0)](char* buffer, size_t capacity) mutable {
        const size_t n = std::min({capacity, piece, xml.size() - at});
        std::memcpy(buffer, xml.data() + at, n);
        at += n;
        return n;
    };
}

}  // namespace ray::test
