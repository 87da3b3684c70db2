#pragma once
// Smooth refinement of a hair mesh with OpenSubdiv: the root topology is refined uniformly and the
// same refinement is applied to every layer, so bundles stay aligned across layers.
#include "hairlod/hairmesh/hair_mesh.h"

namespace hairlod {

// Catmull-Clark (quads or mixed faces) or Loop (all triangles) at `level` in [0, 3]; boundary
// edges and corners are interpolated sharply. Positions and w are refined as vertex data, uv as
// face-varying data with linear interpolation (a texture layout, seams kept). Level 0 returns a copy.
HairMesh subdivide_hair_mesh(const HairMesh& mesh, int level);

}  // namespace hairlod
