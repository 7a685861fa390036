// Transparent huge pages for the few large buffers the loader fills at once.
//
// Filling a fresh buffer faults it in a 4 KiB page at a time, and in a virtual machine with
// memory accounting each fault costs a microsecond or more: loading 10^5 spheres touched
// about 120 MB and spent 0.07 s of 0.5 s in page faults. Where the kernel gives huge pages
// on request only (/sys/kernel/mm/transparent_hugepage/enabled "madvise", as on the
// machine measured), asking for them makes a fault fill 2 MiB. Where it gives them anyway
// ("always") or never, asking changes nothing.
#pragma once

#include <cstddef>
#include <vector>

namespace ray {

// Asks for huge pages over the whole 2 MiB pages inside [data, data + bytes), a buffer
// not yet written. A huge page is resident whole, so a buffer filled only in part may keep
// up to 2 MiB more resident than with small pages: buffers under 8 MiB are left alone.
// Failure is silent: it is advice.
void adviseHugePages(const void* data, size_t bytes);

// The same over a vector's whole capacity: call it after reserve(), before filling.
template <typename T>
void adviseHugePages(const std::vector<T>& buffer) {
    adviseHugePages(buffer.data(), buffer.capacity() * sizeof(T));
}

}  // namespace ray
