#include "primitive_count.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "scene/scene_loader.h"  // the loader's nesting limit (header only)
#include "scene/xml_tree.h"

namespace bench {

namespace {

using ray::XmlElement;

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
const char* attributeAt(XmlElement element, size_t position) {
    return position < element.attributeCount() ? element.attributeValue(position) : nullptr;
}

class PrimitiveCounter {
public:
    explicit PrimitiveCounter(XmlElement scenefile) {
        for (XmlElement e = scenefile.firstChild(); e; e = e.nextSibling())
            if (sameWord(e.name(), "object") && sameWord(attributeAt(e, 0), "tree") && attributeAt(e, 1))
                trees_.emplace(attributeAt(e, 1), e);
    }

    // Throws std::out_of_range for an undefined master, std::logic_error for a cycle.
    uint64_t countTree(const std::string& name) {
        if (auto done = counted_.find(name); done != counted_.end()) return done->second;
        if (!counting_.insert(name).second) throw std::logic_error("cyclic master " + name);
        uint64_t total = countTreeBody(trees_.at(name));
        counting_.erase(name);
        return counted_[name] = total;
    }

private:
    // A tree's children are transblocks, or (tolerated by the loader) bare objects.
    uint64_t countTreeBody(XmlElement tree) {
        uint64_t total = 0;
        for (XmlElement e = tree.firstChild(); e; e = e.nextSibling()) {
            if (sameWord(e.name(), "transblock")) total += countBlock(e);
            else if (sameWord(e.name(), "object")) total += countObject(e);
        }
        return total;
    }

    uint64_t countBlock(XmlElement block) {
        uint64_t total = 0;
        for (XmlElement e = block.firstChild(); e; e = e.nextSibling())
            if (sameWord(e.name(), "object")) total += countObject(e);
        return total;
    }

    uint64_t countObject(XmlElement object) {
        const char* type = attributeAt(object, 0);
        if (sameWord(type, "primitive")) return 1;
        if (sameWord(type, "tree")) return countTreeBody(object);
        if (sameWord(type, "master") && attributeAt(object, 1)) return countTree(attributeAt(object, 1));
        return 0;
    }

    std::map<std::string, XmlElement> trees_;
    std::map<std::string, uint64_t> counted_;
    std::set<std::string> counting_;
};

}  // namespace

std::optional<uint64_t> countPrimitives(const std::filesystem::path& scene) {
    std::ifstream in(scene, std::ios::binary);
    if (!in) return std::nullopt;
    try {
        const ray::XmlTree document = ray::XmlTree::parse(
            [&](char* buffer, size_t capacity) {
                in.read(buffer, std::streamsize(capacity));
                return size_t(in.gcount());
            },
            ray::kMaxElementDepth);
        return PrimitiveCounter(document.root()).countTree("root");
    } catch (const std::exception&) {  // ray::XmlError, or the counter's
        return std::nullopt;
    }
}

}  // namespace bench
