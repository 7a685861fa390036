// The encoding a scene file is written in, and its text to and from UTF-8.
//
// ray's document text is UTF-8 (scene/source_text.h): expat hands names and values over as
// UTF-8, and the splices a save makes are UTF-8. A file read in another encoding XML allows
// and expat reads (ISO-8859-1, US-ASCII, UTF-16 with or without a byte-order mark) keeps it:
// its text is turned into UTF-8 when read and back into its encoding when saved, so that it
// is spliced as any other file is and what no edit touched comes out byte for byte
// (comments, the declaration, the byte-order mark). A character the encoding lacks (a name
// in Greek in an ISO-8859-1 file) is written as a character reference, &#x3A9;, which XML
// reads as the character itself; the only text a save adds is markup in ASCII and attribute
// values, where a reference means what the character does.
#pragma once

#include <string>
#include <string_view>

namespace ray {

enum class TextEncoding { Utf8, Latin1, Ascii, Utf16LE, Utf16BE };

// The encoding expat reads `bytes` in (as XML 1.0's appendix F detects it): UTF-16 by a
// byte-order mark or a first '<' of two bytes, else the one the XML declaration names
// (ISO-8859-1, US-ASCII; UTF-8 when it names none, or UTF-8).
TextEncoding encodingOf(std::string_view bytes);
// "UTF-8", "ISO-8859-1", "US-ASCII", "UTF-16LE", "UTF-16BE".
const char* encodingName(TextEncoding encoding);

// `bytes`, in `encoding`, as UTF-8 (a byte-order mark becomes U+FEFF, kept). Bytes that are
// not the encoding's (which expat refuses, except after the root element, which it does
// not read) become U+FFFD.
std::string toUtf8(std::string_view bytes, TextEncoding encoding);
// UTF-8 `text` in `encoding`; a character the encoding cannot hold is written as a
// character reference (&#x...;).
std::string fromUtf8(std::string_view text, TextEncoding encoding);

}  // namespace ray
