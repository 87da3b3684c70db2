#pragma once
// The LoD asset of hair-lod-aggregated-bcsdf.txt Sec. 5.1: guide hairs, L0 clusters of strands
// sharing their 3 nearest guides, finer thick-hair levels split from L0, elliptical cross-sections
// and linear-skinning coordinates, built from any StrandSet.
#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "hairlod/core/error.h"
#include "hairlod/core/strand_set.h"
#include "hairlod/lod/compact.h"
#include "hairlod/lod/guide_frame.h"
#include "hairlod/lod/width_ellipsoid.h"

namespace hairlod {

// Progress of a build that another thread watches and may cancel (Blender's modal operator).
struct LodBuildProgress {
    std::atomic<int> done{0};          // steps finished
    std::atomic<int> total{1};         // steps of the whole build, set when it starts
    std::atomic<bool> cancel{false};   // set to stop the build at its next step
};

// Thrown by build_lod when LodBuildProgress::cancel was set.
class LodBuildCancelled : public Error {
public:
    LodBuildCancelled() : Error("build_lod: cancelled") {}
};

// The ranges build_lod accepts: levels (thick levels plus the strands) and control points per hair.
inline constexpr int kMinLevels = 2;
inline constexpr int kMaxLevels = 16;
inline constexpr int kMinControlPoints = 2;

// Every default here is the tools' default too (CLI, Python API, Blender settings: hairlod._core.LOD_DEFAULTS).
struct LodOptions {
    int guides = 0;            // k of the guide k-means; 0: auto_guide_count(strand count)
    int levels = 6;            // n_L at most: thick-hair levels L0 .. L_{n_L - 2}, then the strands
    int control_points = 16;   // n_c per strand and per thick hair
    uint64_t seed = 0;
    int max_kmeans_iterations = 20;  // Lloyd updates for the guides
    double kmeans_stop_fraction = 1e-3;  // ... or fewer once an update moves at most this fraction of strands
    int arc_length_subdivisions = 4;     // per input segment when resampling (see ResampleOptions)
    float ellipse_coverage = 0.95f;  // fraction of member control points each ellipse must hold
    LodBuildProgress* progress = nullptr;  // optional: steps reported, cancellation checked between them
};

// One level of thick hairs. Hairs are ordered by L0 cluster: cluster c owns hairs
// [cluster_first[c], cluster_first[c + 1]). Per-control-point arrays hold hairs * n_c entries.
// Strands are stored in hierarchy order (LodAsset::strand_order), so the members of hair h are the
// contiguous positions [member_first[h], member_first[h + 1]) on every level.
// Cross-sections are held compactly (compact.h); LodAsset::section decodes them. They are derived
// from the members (fit_sections), so files may leave them out. Coverage and
// mean_area are measured on the decoded ellipses. The 4 corner control points of Sec. 5.1 step 3
// are the ends of the decoded axes, skinned like the centre, so they need no storage.
struct ThickHairLevel {
    std::vector<int32_t> cluster_first;
    std::vector<int32_t> parent;        // the hair one level coarser holding it (-1 on L0)
    std::vector<int32_t> member_first;  // [hairs + 1] offsets into the hierarchy order
    std::vector<glm::u16vec3> centre_offset;  // from the L0 cluster's rest frame origin, LodAsset::offset_boxes
    std::vector<glm::i16vec2> major_axis;    // unit, rest pose, octahedral
    std::vector<uint16_t> minor_axis;        // unit, perpendicular to the decoded major axis
    std::vector<glm::u16vec2> radii;         // (major, minor), halves rounded up, LodAsset::radius_exponent
    double coverage = 0.0;    // fraction of member control points inside their ellipse
    double mean_area = 0.0;   // mean over hairs and control points of pi r_A r_B

    size_t hair_count() const { return parent.size(); }
    int32_t n_total(size_t hair) const { return member_first[hair + 1] - member_first[hair]; }

    // Calls visit(name, array) for every array, in a fixed order (serialisation, memory): the
    // hierarchy (visit_hierarchy_arrays), then the cross-sections (visit_section_arrays).
    template <typename Level, typename Visit>
    static void visit_arrays(Level& level, Visit&& visit) {
        visit_hierarchy_arrays(level, visit);
        visit_section_arrays(level, visit);
    }
    template <typename Level, typename Visit>
    static void visit_hierarchy_arrays(Level& level, Visit&& visit) {
        visit("cluster_first", level.cluster_first);
        visit("parent", level.parent);
        visit("member_first", level.member_first);
    }
    template <typename Level, typename Visit>
    static void visit_section_arrays(Level& level, Visit&& visit) {
        visit("centre_offset", level.centre_offset);
        visit("major_axis", level.major_axis);
        visit("minor_axis", level.minor_axis);
        visit("radii", level.radii);
    }
};

// One decoded rest cross-section of a thick hair.
struct RestSection {
    glm::vec3 centre_offset{0.0f};  // from the L0 cluster's rest frame origin (world axes)
    glm::vec3 major_axis{0.0f};    // unit, world
    glm::vec3 minor_axis{0.0f};
    glm::vec2 radii{0.0f};
};

// Positions of everything drawable, for the rest pose or deformed guides.
struct ThickHairGeometry {
    std::vector<glm::vec3> centre;   // [hairs * n_c]
    std::vector<glm::vec3> tangent;  // unit, from the centre curve
    std::vector<glm::vec3> major;    // semi-axis vectors (axis * radius)
    std::vector<glm::vec3> minor;
    std::vector<std::array<glm::vec3, 4>> corners;  // centre +- major, centre +- minor
    // Per L0 cluster and control point [clusters * n_c]: the centre (xyz) and corner diameter (w)
    // of the cluster's widest hair there, the diameter measured between the corners projected onto
    // the plane normal to the tangent (Sec. 5.2), the ellipsoid holding the semi-axes of all its
    // hairs there (width_ellipsoid.h) and that ellipsoid's thinnest diameter. All the per-frame
    // selection reads.
    std::vector<glm::vec4> widest;
    std::vector<SymmetricEntries> width_ellipsoid;
    std::vector<float> thinnest;
};

struct LodGeometry {
    StrandSet strands;                       // n_c points per strand
    std::vector<ThickHairGeometry> levels;   // one per thick level
    std::vector<glm::vec4> cluster_bounds;   // per L0 cluster: bounding sphere (centre, radius) of its strands
};

struct LodBuildTimings {  // seconds
    double resample = 0, kmeans = 0, clusters = 0, levels = 0, fitting = 0, weights = 0;
};

struct LodAsset {
    int control_points = 0;
    std::vector<int64_t> guide_strands;  // the strand each guide is (a k-means medoid)
    std::vector<glm::vec3> rest_guides;  // [guides * n_c], resampled guide strands
    std::vector<std::array<int32_t, 3>> cluster_guides;  // per L0 cluster, sorted, -1 padded
    std::vector<FrameKind> frame_kinds;  // [L0 clusters * n_c]
    // Hierarchy order: position i holds input strand strand_order[i]; the finest thick level's
    // hairs follow each other, so every hair of every level (and every L0 cluster) is a range of
    // positions. Per-strand arrays below are indexed by position.
    std::vector<int32_t> strand_order;
    // Per L0 cluster and control point [clusters * n_c]: the box of its strands' offsets (which
    // holds its thick-hair centres too, their means) that quantises both. A decoded rest point is
    // off by at most |step| / 2 (world units), 1/131070 of the box diagonal, plus float rounding; and
    // a rigid motion moves the decoded point rigidly.
    std::vector<QuantisationBox> offset_boxes;
    std::vector<glm::u16vec3> strand_offset;  // [strands * n_c], from the L0 cluster's rest frame origin
    // Halves rounded up: [strands] where every strand's radius is the same along it (stored once per
    // strand, as generated and most groomed hair has it), else [strands * n_c].
    std::vector<uint16_t> strand_radius;
    // Radii (strands' and thick hairs') are stored as halves of radius * 2^-radius_exponent, the
    // exponent putting the largest radius near 2^10: ample range both ways within the half's.
    int radius_exponent = 0;
    // The fraction of member control points each ellipse holds (LodOptions::ellipse_coverage): the
    // cross-sections are a function of the stored strands and this (fit_sections).
    float ellipse_coverage = LodOptions{}.ellipse_coverage;
    std::vector<ThickHairLevel> thick_levels;  // L0 first; the strands are level thick_levels.size()
    LodBuildTimings timings;

    size_t strand_count() const { return strand_order.size(); }
    size_t guide_count() const { return guide_strands.size(); }
    size_t cluster_count() const { return cluster_guides.size(); }
    size_t level_count() const { return thick_levels.size() + 1; }
    size_t memory_bytes() const;  // held in memory: stored_bytes() and the cross-sections
    size_t stored_bytes() const;  // what a file or pack holds (the cross-sections are fitted on reading)
    // The radius code of the strand at hierarchy position i, control point k (either layout).
    uint16_t strand_radius_code(size_t i, size_t k) const {
        return strand_radius.size() == strand_order.size() ? strand_radius[i]
                                                           : strand_radius[i * static_cast<size_t>(control_points) + k];
    }
    // Positions of the strands of L0 cluster c: [first, second).
    std::pair<int32_t, int32_t> cluster_strands(size_t c) const {
        // Through cluster_first, so that it holds for any coarsest kept level (with_levels).
        const ThickHairLevel& coarsest = thick_levels[0];
        return {coarsest.member_first[static_cast<size_t>(coarsest.cluster_first[c])],
                coarsest.member_first[static_cast<size_t>(coarsest.cluster_first[c + 1])]};
    }
    // Per input strand: the hair of thick level `level` holding it.
    std::vector<int32_t> strand_hairs(size_t level) const;
    // The rest cross-section of `hair` of thick level `level` at control point k.
    RestSection section(size_t level, size_t hair, size_t k) const;
    // Per hair and control point of thick level `level`: the density of Sec. 4,
    // rho = n_total r^2 / (|r_A| |r_B|), r the members' mean radius there (derived, not stored).
    std::vector<float> density(size_t level) const;

    // Calls visit(name, array) for every stored array outside the levels, in a fixed order.
    template <typename Asset, typename Visit>
    static void visit_arrays(Asset& asset, Visit&& visit) {
        visit("guide_strands", asset.guide_strands);
        visit("rest_guides", asset.rest_guides);
        visit("cluster_guides", asset.cluster_guides);
        visit("frame_kinds", asset.frame_kinds);
        visit("strand_order", asset.strand_order);
        visit("offset_boxes", asset.offset_boxes);
        visit("strand_offset", asset.strand_offset);
        visit("strand_radius", asset.strand_radius);
    }

    // Throws Error naming the first array whose size or indices are inconsistent (an asset read
    // back from files must be checked before skinning indexes with it).
    void validate() const;
    // The same checks except the thick levels' cross-sections: what fit_sections needs.
    void validate_structure() const;

    // A copy keeping only the thick levels at positions `kept` (L0 first); each kept level's parents
    // point to the next kept coarser level, composed through the dropped ones (-1 on the first kept).
    // Throws Error unless `kept` is a non-empty, strictly increasing list of existing levels.
    LodAsset with_levels(std::span<const size_t> kept) const;

    // Skins strands and thick hairs to `deformed_guides` ([guides * n_c] points, the guides in the
    // order of guide_strands) by the linear skinning of Sec. 5.1 step 4 / Sec. 5.2 (skinning.h;
    // skin_geometry there keeps what this derives from the rest pose for a sequence of frames).
    LodGeometry skin(std::span<const glm::vec3> deformed_guides) const;
    // The decoded rest pose (the same as skin(rest_guides) up to float rounding, without deriving
    // the stencils).
    LodGeometry rest_geometry() const;
};

// Fits every thick hair's rest cross-sections (Sec. 5.1 step 3: at the members' k-th points' mean,
// PCA axes and radii holding ellipse_coverage of where the members cross the plane normal to their
// mean tangent, cross_section.h) to its member strands as the asset stores them, and
// stores them with each level's coverage and mean area. build_lod ends with it; an asset read back
// without its cross-sections (they take about a quarter of its bytes) gets the same ones from it.
// Needs validate_structure(); throws Error for an ellipse_coverage outside (0, 1].
void fit_sections(LodAsset& asset);

// The default guide count: one guide per kStrandsPerGuide strands, from kMinAutoGuides (or every
// strand, when there are fewer) to kMaxAutoGuides. L0 clusters (strands sharing their 3 nearest
// guides, about 3-5 clusters per guide) then hold tens of strands on a few thousand strands and
// about a hundred on 10^5, room for thick levels 4x apart in area below them.
inline constexpr int kStrandsPerGuide = 128, kMinAutoGuides = 16, kMaxAutoGuides = 256;
int auto_guide_count(size_t strand_count);

// Builds the asset; throws Error for invalid strands or options, LodBuildCancelled when cancelled.
// Each thick hair splits into as many children as bring the mean cross-section area about 4x
// down (Sec. 5.1 step 2), while the children keep at least 4 strands on average; a hair that
// cannot split is carried to the next level unchanged. Levels stop when no hair splits, or at
// options.levels - 1 thick levels.
LodAsset build_lod(const StrandSet& strands, const LodOptions& options = {});

}  // namespace hairlod
