// Scenes of 10^k spheres for the scaling curve, written with masters so that even a
// million spheres is a few kilobytes of XML (SPEC §1).
#pragma once

#include <filesystem>

namespace bench {

// Writes a scene of 10^levels spheres (plus a floor cube) to `file`.
//
// Tree L1 holds 10 spheres at random places and sizes inside the unit box; tree Lk holds 10
// instances of L(k-1), each scaled down and moved to a random sub-box of the unit box; the
// root holds the floor and one instance of L<levels>, scaled to a 10-unit box. Each level
// draws from its own fixed seed, so Lk is the same in every scene that contains it and the
// files are identical from run to run and machine to machine.
void writeSphereScene(const std::filesystem::path& file, int levels);

}  // namespace bench
