#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>

#include "core/huge_pages.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>

namespace {
// Where the blocks' addresses go, so that the compiler cannot leave out their malloc and free.
void* volatile escaped = nullptr;
}  // namespace

TEST_CASE("a large block is unmapped when freed, however large the blocks freed before it", "[memory]") {
    ray::returnLargeBlocksWhenFreed();
    // glibc's default would now raise its threshold to 24 MiB and serve the next block
    // from the heap, where freeing it returns nothing to the system.
    void* big = std::malloc(24u << 20);
    REQUIRE(big);
    std::memset(big, 1, 24u << 20);
    escaped = big;
    std::free(big);
    const size_t mappedBefore = mallinfo2().hblkhd;
    void* next = std::malloc(ray::kLargeBlockBytes + (1u << 20));
    REQUIRE(next);
    escaped = next;
    CHECK(mallinfo2().hblkhd >= mappedBefore + ray::kLargeBlockBytes + (1u << 20));
    std::free(next);
    CHECK(mallinfo2().hblkhd == mappedBefore);
}
#endif
