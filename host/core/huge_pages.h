// The ray command's heap: transparent huge pages, and large blocks given back when freed.
//
// Loading a large scene writes hundreds of megabytes of fresh memory (the XML, its tree, the
// instances, the packed tables), and the kernel maps each 4 KiB page of it on first touch:
// on 10^5 spheres 52,000 page faults, which took about 40% of the load on the machines
// measured (docs/performance.md, "Loading"). glibc's malloc asks for 2 MiB pages instead
// (madvise(MADV_HUGEPAGE) on its heap and on its large blocks) when the tunable
// glibc.malloc.hugetlb=1 is in the environment, but it reads tunables once, before main.
// So the ray command runs itself again, once, with the tunable added.
#pragma once

namespace ray {

// Replaces the process with the same program and arguments under
// GLIBC_TUNABLES=...:glibc.malloc.hugetlb=1, unless that would change nothing or is not
// wanted: the tunable is set already (by this function's first run or by the user),
// RAY_HUGE_PAGES=0, the kernel has transparent huge pages off ("never"), or malloc is not
// glibc's (sanitizer builds). Returns only when it does not replace the process (an exec
// that fails too: the program then runs on with 4 KiB pages). Call it first in main(),
// before any thread starts.
void restartWithHugePageHeap(char** argv);

// Blocks of kLargeBlockBytes and more are mapped on their own and unmapped when freed, at any
// time in the run. glibc's malloc does so at first, but raises that threshold to the size of
// each such block freed (up to 32 MiB), so that after the packing of a mesh has freed its
// triangles' boxes, the next blocks of a few MiB come from the heap, where what is freed
// stays resident: on 1 M triangles 30 MB more at the peak (docs/performance.md, "Meshes:
// memory and scaling"). Does nothing where malloc is not glibc's. Call it at the start of main().
constexpr unsigned long kLargeBlockBytes = 4ul << 20;
void returnLargeBlocksWhenFreed();

}  // namespace ray
