// Ids across a reload (edit_session.h): the scene file read again is a new document, whose
// loader numbers its elements from 0 in the file's order; an element added above another
// by some other program would give that one the id of its neighbour, and an edit made
// with the old id (a page that has not seen the reload yet, a script) would change or
// delete the wrong element. So the new document's elements that are the same as the old
// one's keep the old ids, and the others get ids the old document never used.
//
// "The same": top-level trees by name; in each list (a tree's transblocks, a transblock's
// items, the lights) the elements alike in content (their transforms, shapes, materials,
// files, masters' names: not their lines, which move): the first and last runs that are
// alike, then alike ones in the run between; between two such pairs in order, what is left
// is paired in order when as many are left on each side, of the same kind: an element
// edited in place (its colour changed) stays itself, and a transblock's items are then
// matched the same way.
#pragma once

#include "scene/scene_document.h"

namespace ray::edit {

// Gives every node of `fresh` (trees, transblocks, objects, placements, csg objects,
// lights) an id: the id of the element of `old` it matches, or a new one past `old`'s
// counters (whose successors `fresh` then keeps).
void keepIdsAcrossReload(const SceneDocument& old, SceneDocument& fresh);

}  // namespace ray::edit
