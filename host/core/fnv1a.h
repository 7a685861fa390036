// FNV-1a, 64 bits: the hash ray uses to tell whether bytes changed (a scene file on disk, a
// recovery copy, an element of a reloaded document). Fast and stable across runs and
// machines; not for an adversary (nothing here is one: the files are the user's own).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ray {

class Fnv1a {
public:
    void add(const void* data, size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < size; ++i) state_ = (state_ ^ p[i]) * 1099511628211ull;
    }
    void add(std::string_view bytes) { add(bytes.data(), bytes.size()); }
    uint64_t value() const { return state_; }

private:
    uint64_t state_ = 14695981039346656037ull;
};

inline uint64_t fnv1a(std::string_view bytes) {
    Fnv1a hash;
    hash.add(bytes);
    return hash.value();
}

}  // namespace ray
