#include "primitive_count.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace bench {

namespace {

using tinyxml2::XMLElement;

// Element names and keywords are matched ignoring case, as the loader does.
bool sameWord(const char* a, const char* b) {
    if (!a || !b) return false;
    std::string x(a), y(b);
    auto lower = [](std::string s) {
        std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return s;
    };
    return lower(x) == lower(y);
}

// Attributes are positional (SPEC §1): an object's first is its type, the second its name.
const char* attributeAt(const XMLElement& element, int position) {
    const tinyxml2::XMLAttribute* attribute = element.FirstAttribute();
    for (int i = 0; attribute && i < position; ++i) attribute = attribute->Next();
    return attribute ? attribute->Value() : nullptr;
}

class PrimitiveCounter {
public:
    explicit PrimitiveCounter(const XMLElement& scenefile) {
        for (const XMLElement* e = scenefile.FirstChildElement(); e; e = e->NextSiblingElement())
            if (sameWord(e->Name(), "object") && sameWord(attributeAt(*e, 0), "tree") && attributeAt(*e, 1))
                trees_.emplace(attributeAt(*e, 1), e);
    }

    // Throws std::out_of_range for an undefined master, std::logic_error for a cycle.
    uint64_t countTree(const std::string& name) {
        if (auto done = counted_.find(name); done != counted_.end()) return done->second;
        if (!counting_.insert(name).second) throw std::logic_error("cyclic master " + name);
        uint64_t total = countTreeBody(*trees_.at(name));
        counting_.erase(name);
        return counted_[name] = total;
    }

private:
    // A tree's children are transblocks, or (tolerated by the loader) bare objects.
    uint64_t countTreeBody(const XMLElement& tree) {
        uint64_t total = 0;
        for (const XMLElement* e = tree.FirstChildElement(); e; e = e->NextSiblingElement()) {
            if (sameWord(e->Name(), "transblock")) total += countBlock(*e);
            else if (sameWord(e->Name(), "object")) total += countObject(*e);
        }
        return total;
    }

    uint64_t countBlock(const XMLElement& block) {
        uint64_t total = 0;
        for (const XMLElement* e = block.FirstChildElement(); e; e = e->NextSiblingElement())
            if (sameWord(e->Name(), "object")) total += countObject(*e);
        return total;
    }

    uint64_t countObject(const XMLElement& object) {
        const char* type = attributeAt(object, 0);
        if (sameWord(type, "primitive")) return 1;
        if (sameWord(type, "tree")) return countTreeBody(object);
        if (sameWord(type, "master") && attributeAt(object, 1)) return countTree(attributeAt(object, 1));
        return 0;
    }

    std::map<std::string, const XMLElement*> trees_;
    std::map<std::string, uint64_t> counted_;
    std::set<std::string> counting_;
};

}  // namespace

std::optional<uint64_t> countPrimitives(const std::filesystem::path& scene) {
    tinyxml2::XMLDocument document;
    if (document.LoadFile(scene.c_str()) != tinyxml2::XML_SUCCESS) return std::nullopt;
    const XMLElement* root = document.FirstChildElement();
    if (!root) return std::nullopt;
    try {
        return PrimitiveCounter(*root).countTree("root");
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace bench
