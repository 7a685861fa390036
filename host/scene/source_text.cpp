// The file's text and its elements' places (source_text.h).
#include "scene/source_text.h"

#include <algorithm>
#include <stdexcept>

namespace ray {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool isNameEnd(char c) { return isBlank(c) || c == '=' || c == '/' || c == '>'; }

}  // namespace

std::string applySplices(std::string_view original, std::vector<Splice> splices) {
    // At one place, insertions come before a replacement that starts there (a transform
    // written where the one it replaces was).
    std::stable_sort(splices.begin(), splices.end(), [](const Splice& a, const Splice& b) {
        return a.begin != b.begin ? a.begin < b.begin : (a.end == a.begin && b.end != b.begin);
    });
    std::string out;
    out.reserve(original.size());
    size_t at = 0;
    for (const Splice& s : splices) {
        if (s.begin < at || s.end < s.begin || s.end > original.size())
            throw std::logic_error("overlapping splices at byte " + std::to_string(s.begin));
        out.append(original.substr(at, s.begin - at));
        out += s.text;
        at = s.end;
    }
    out.append(original.substr(at));
    return out;
}

SourceText::SourceText(std::string text, XmlTree tree, TextEncoding encoding, std::string fileBytes)
    : bytes_(std::move(text)), tree_(std::move(tree)), encoding_(encoding), fileBytes_(std::move(fileBytes)) {
    if (!tree_.hasSpans()) throw std::logic_error("SourceText needs a tree parsed with spans");
    parents_.assign(tree_.elementCount(), kNoSource);
    bool unitFound = false;
    // Elements come in document order: every parent before its children.
    for (SourceId id = 0; id < tree_.elementCount(); ++id)
        for (XmlElement child = element(id).firstChild(); child; child = child.nextSibling()) {
            parents_[child.index()] = id;
            if (unitFound) continue;
            const auto outer = indentation(id), inner = indentation(child.index());
            if (outer && inner && inner->size() > outer->size() && inner->substr(0, outer->size()) == *outer) {
                indentUnit_ = std::string(inner->substr(outer->size()));
                unitFound = true;
            }
        }
    if (bytes_.find("\r\n") != std::string::npos) newline_ = "\r\n";
}

std::string SourceText::fileBytes(const std::string& text) const {
    if (encoding_ == TextEncoding::Utf8) return text;
    if (text == bytes_) return fileBytes_;
    return fromUtf8(text, encoding_);
}

std::optional<std::string_view> SourceText::indentation(SourceId id) const {
    const size_t begin = size_t(span(id).begin);
    size_t lineStart = begin;
    while (lineStart > 0 && bytes_[lineStart - 1] != '\n') --lineStart;
    const std::string_view before(bytes_.data() + lineStart, begin - lineStart);
    if (!std::all_of(before.begin(), before.end(), [](char c) { return c == ' ' || c == '\t'; })) return std::nullopt;
    return before;
}

std::pair<size_t, size_t> SourceText::removalRange(SourceId id) const {
    const size_t begin = size_t(span(id).begin), end = size_t(span(id).end);
    const std::optional<std::string_view> indent = indentation(id);
    size_t after = end;
    while (after < bytes_.size() && (bytes_[after] == ' ' || bytes_[after] == '\t' || bytes_[after] == '\r')) ++after;
    const bool ownsLines = indent && (after == bytes_.size() || bytes_[after] == '\n');
    if (!ownsLines) return {begin, end};
    return {begin - indent->size(), after < bytes_.size() ? after + 1 : after};
}

std::vector<SourceText::Attribute> SourceText::attributes(SourceId id) const {
    std::vector<Attribute> result;
    const XmlSpan& s = span(id);
    size_t at = size_t(s.begin) + 1;  // past '<'
    const size_t end = size_t(s.startTagEnd);
    while (at < end && !isNameEnd(bytes_[at])) ++at;  // the element's name
    for (;;) {
        while (at < end && isBlank(bytes_[at])) ++at;
        if (at >= end || bytes_[at] == '/' || bytes_[at] == '>') break;
        const size_t nameBegin = at;
        while (at < end && !isNameEnd(bytes_[at])) ++at;
        Attribute attribute;
        attribute.name = std::string_view(bytes_.data() + nameBegin, at - nameBegin);
        while (at < end && bytes_[at] != '\'' && bytes_[at] != '"') ++at;  // blanks, '=', blanks
        if (at >= end) break;  // not well-formed: expat would have refused it
        attribute.quote = bytes_[at];
        attribute.valueBegin = ++at;
        while (at < end && bytes_[at] != attribute.quote) ++at;
        attribute.valueEnd = at++;
        result.push_back(attribute);
    }
    return result;
}

size_t SourceText::attributeInsertion(SourceId id) const {
    const std::vector<Attribute> written = attributes(id);
    if (!written.empty()) return written.back().valueEnd + 1;  // past the closing quote
    size_t at = size_t(span(id).begin) + 1;
    while (!isNameEnd(bytes_[at])) ++at;
    return at;
}

}  // namespace ray
