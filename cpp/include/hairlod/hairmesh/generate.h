#pragma once
// Strand generation from a hair mesh (hair-meshes-realtime.txt Sec. 3): roots by blue-noise sample
// sets, centripetal Catmull-Rom curves through the layers, styling in the styling frames, tangents
// and level of detail. The output StrandSet carries the point attributes "tangent" (3) and "uvw"
// (3) and the curve attribute "bundle" (root face index, as float).
#include <cstdint>
#include <vector>

#include "hairlod/core/strand_set.h"
#include "hairlod/hairmesh/hair_mesh.h"
#include "hairlod/hairmesh/root_samples.h"
#include "hairlod/hairmesh/styling.h"
#include "hairlod/hairmesh/styling_frames.h"

namespace hairlod {

struct GenerateOptions {
    size_t count = 1000;   // strands at full strand LoD, distributed over bundles by root face area
    int vertices = 17;     // vertices per strand at full vertex LoD: 2^E + 1, E in [0, 12]
    std::vector<StylingOperation> styling;
    uint64_t seed = 0;
    float strand_lod = 1.0f;      // L of Bhokare 2024 Eq. 8, in (0, 1]
    float vertex_lod = 1.0f;      // L of Bhokare 2024 Eq. 9, in (0, 1]
    float lod_transition = 0.5f;  // lambda of Bhokare 2024 Eq. 10, in (0, 1]
    float radius = 0.0f;          // strand radius at full LoD, object units
};

// Throws Error naming the first option that is out of range.
void validate_options(const GenerateOptions& options);

// Strands of each bundle at full LoD: `count` split in proportion to root face area by largest
// remainders (ties to the lower face index), so the counts sum to `count` exactly. Faces of zero
// area get none; a root layer of zero total area is an Error.
std::vector<int64_t> bundle_strand_counts(const HairMesh& mesh, size_t count);

// Sample sets large enough for `options` on `mesh`: 4 sets per domain of the next power of two at
// or above the largest bundle count, seeded by options.seed. When `reuse` holds exactly the sets
// that would be built (same size, seed and families, as after most edits that move hair-mesh
// vertices), a copy of it is returned instead of building them again.
RootSampleSets root_sample_sets_for(const HairMesh& mesh, const GenerateOptions& options,
                                    const RootSampleSets* reuse = nullptr);

// The full pipeline with precomputed frames and sample sets (both depend only on the mesh and the
// seed, so interactive callers reuse them). Parallel over strands; deterministic for a seed.
// Writes into `output`, reusing its storage: an interactive viewer regenerating strands of the
// same size every frame allocates (and page-faults) nothing. Other attributes of `output` are dropped.
void generate_strands(const HairMesh& mesh, const StylingFrames& frames, const RootSampleSets& samples,
                      const GenerateOptions& options, StrandSet& output);

StrandSet generate_strands(const HairMesh& mesh, const GenerateOptions& options);

}  // namespace hairlod
