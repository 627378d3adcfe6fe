// Initial states that are not physical, named before a run starts (docs/scenes.md, "Initial
// states checked"): particles placed through each other or through a wall, and particles that
// lie behind a wall or outside a container. Both solvers start from initial_particles(); `talus
// run` checks its result here before stepping.
#pragma once

#include <string>
#include <vector>

#include "solver/scene/scene.hpp"

namespace talus {

// Checks the initial particles of `scene` (initial_particles(scene); a particle's id is its
// index). Errors, thrown as SceneError at the scene entry of the first particle named:
//  - two particles so deep in each other that the centroid of one lies inside the other
//    (identical poses among them): the contact law cannot separate such a pair;
//  - a particle whose body crosses a wall with its centroid behind it (on the side away from the
//    particles): the wall's contact pushes it along the wall's normal, through the wall.
// Warnings, returned one line each ("<file>:<line>:<column>: <key>: warning: ..."), grouped by
// scene entry so that a lattice of 1e6 gives a line, not 1e6, each naming the first few ids:
//  - overlapping particles (shallower than the error): the contact law pushes them apart at the
//    first step, releasing the overlap's elastic energy as speed;
//  - particles whose body crosses a wall with their centroid on the particles' side;
//  - particles outside a closed container (a box without open_top, a drum, a cylinder with both
//    caps), which they can never enter;
//  - particles wholly behind any other wall, where they can reach the particles' side only
//    around it: behind a plane's square; outside an open box, cylinder, hopper or silo beside
//    its side wall (within its axial extent) or beneath its floor, cap, flat bottom or closed
//    outlet; behind the triangle of a mesh wall they are nearest to, projecting onto its inside;
//  - a random fill with particles on both sides of a wall: its region reaches beyond it (one
//    line on the fill's entry, in place of the line above).
// docs/scenes.md lists what each wall kind leaves unchecked. O(n log n): the broad phase's
// candidate pairs (neighbor/contact_pairs.hpp), a grid of the walls' triangles (placement.hpp),
// the generated walls' shapes in closed form and a tree of each mesh wall's triangles.
std::vector<std::string> check_initial_state(const Scene& scene,
                                             const std::vector<ParticleState>& particles);

}  // namespace talus
