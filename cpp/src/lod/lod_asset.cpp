#include "hairlod/lod/lod_asset.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "hairlod/core/error.h"
#include "hairlod/curves/resample.h"
#include "hairlod/lod/cross_section.h"
#include "hairlod/lod/kmeans.h"
#include "hairlod/lod/skinning.h"

namespace hairlod {

namespace {

// Sec. 5.1 step 2: the thick-hair cross-section area shrinks about 4x per level.
constexpr double kLevelAreaRatio = 4.0;
// Children of a split keep at least this many strands on average: fewer (2 or 3 strands, often
// nearly in a line) leave slivers no wider than the strands themselves.
constexpr double kFinestHairStrands = 4.0;
// Splits tried per hair to reach kLevelAreaRatio; the area measured at this many control points.
constexpr int kSplitAttempts = 3;
constexpr size_t kAreaSamples = 4;
// A split must shrink the mean area at least this much (the geometric middle of 1 and 4), else
// the hair is carried whole: a level barely finer than its parent costs bytes and draws as much.
constexpr double kMinSplitAreaRatio = 2.0;
// A whole level must shrink the mean area (over its hairs, carried ones included) at least this
// much, the low end of "about 4x": a finer level would be mostly a copy of the one above, so the
// thick levels stop there and the strands come next.
constexpr double kMinLevelAreaRatio = 3.0;
// The largest radius is stored near 2^10 (LodAsset::radius_exponent): room above for the growth
// that keeps coverage (the half's largest is about 2^16) and 24 binades below in full precision.
constexpr int kRadiusHeadroomBits = 10;

// One step of the build done: cancels if asked, else counts it.
void report_step(LodBuildProgress* progress) {
    if (progress == nullptr) return;
    if (progress->cancel.load(std::memory_order_relaxed)) throw LodBuildCancelled();
    progress->done.fetch_add(1, std::memory_order_relaxed);
}

class Stopwatch {
public:
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return seconds;
    }

private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Flattened control points, centred on the hair's mean point so that squared distances keep
// their precision for hair far from the origin.
std::vector<float> centred_features(const StrandSet& resampled) {
    glm::dvec3 mean(0.0);
    for (const glm::vec3& p : resampled.points) mean += glm::dvec3(p);
    mean /= static_cast<double>(resampled.points.size());
    std::vector<float> features(resampled.points.size() * 3);
    tbb::parallel_for(size_t{0}, resampled.points.size(), [&](size_t i) {
        const glm::vec3 p(glm::dvec3(resampled.points[i]) - mean);
        features[3 * i] = p.x;
        features[3 * i + 1] = p.y;
        features[3 * i + 2] = p.z;
    });
    return features;
}

// Sec. 5.1 step 1: k-means guides, each the exact medoid of its (non-empty) cluster.
std::vector<int64_t> select_guides(const FeatureRows& rows, const LodOptions& options) {
    const int count = options.guides > 0 ? options.guides : auto_guide_count(rows.size());
    std::vector<float> seeds = kmeans_plus_plus_seeds(rows, static_cast<size_t>(count), options.seed);
    const KMeansResult clusters =
        kmeans(rows, std::move(seeds), options.max_kmeans_iterations, options.kmeans_stop_fraction);
    std::vector<int64_t> guides;
    for (int64_t medoid : cluster_medoids(rows, group_by_cluster(clusters.assignment, clusters.centres.size() / rows.dim)))
        if (medoid >= 0) guides.push_back(medoid);
    return guides;
}

// Sec. 5.1 step 2: each strand's (up to) 3 nearest guides as a sorted set, -1 padded.
std::vector<std::array<int32_t, 3>> nearest_guide_sets(const FeatureRows& rows, std::span<const int64_t> guides) {
    std::vector<std::array<int32_t, 3>> sets(rows.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rows.size()), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
            std::array<float, 3> best{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                                      std::numeric_limits<float>::infinity()};
            std::array<int32_t, 3> ids{-1, -1, -1};
            for (size_t g = 0; g < guides.size(); ++g) {
                float d = squared_distance(rows.row(i), rows.row(static_cast<size_t>(guides[g])), rows.dim);
                if (d >= best[2]) continue;
                auto id = static_cast<int32_t>(g);
                for (int slot = 0; slot < 3; ++slot)
                    if (d < best[slot]) {
                        std::swap(d, best[slot]);
                        std::swap(id, ids[slot]);
                    }
            }
            // Sorted with the -1 padding last, so the set is a key independent of distance order.
            std::sort(ids.begin(), ids.end(), [](int32_t a, int32_t b) { return static_cast<uint32_t>(a) < static_cast<uint32_t>(b); });
            sets[i] = ids;
        }
    });
    return sets;
}

std::vector<glm::vec3> unit_tangents(const StrandSet& resampled, int control_points) {
    std::vector<glm::vec3> tangents(resampled.points.size());
    const auto nc = static_cast<size_t>(control_points);
    tbb::parallel_for(size_t{0}, resampled.curve_count(), [&](size_t s) {
        const glm::vec3* p = resampled.points.data() + s * nc;
        for (size_t k = 0; k < nc; ++k) {
            const glm::vec3 step = p[std::min(k + 1, nc - 1)] - p[k == 0 ? 0 : k - 1];
            const float length = glm::length(step);
            tangents[s * nc + k] = length > 0.0f ? step / length : glm::vec3(0.0f);
        }
    });
    return tangents;
}

// One group of strands per thick hair of a level, in hair order.
using Groups = std::vector<std::vector<int32_t>>;

// Reused buffers of member_section.
struct SectionScratch {
    std::vector<glm::vec3> points, tangents;
    std::vector<float> distances;
};

// Sec. 5.1 step 3 at control point k for the strands `members` (indices into `strands`, n_c points
// each; unit `tangents` per point): the ellipse holding `coverage` of where the members cross the
// plane through their k-th points' mean normal to their mean tangent (strand_plane_crossing). Where
// the tangents cancel, of the k-th points themselves (PCA, the axis closest to the tangent dropped).
CrossSection member_section(std::span<const int32_t> members, const StrandSet& strands, const std::vector<glm::vec3>& tangents,
                            size_t nc, size_t k, float coverage, SectionScratch& scratch) {
    const size_t m = members.size();
    scratch.points.resize(m);
    scratch.tangents.resize(m);
    glm::dvec3 centre(0.0), mean_tangent(0.0);
    double radius = 0.0;
    for (size_t j = 0; j < m; ++j) {
        const size_t at = static_cast<size_t>(members[j]) * nc + k;
        scratch.points[j] = strands.points[at];
        scratch.tangents[j] = tangents[at];
        centre += glm::dvec3(strands.points[at]);
        mean_tangent += glm::dvec3(tangents[at]);
        radius += strands.radius[at];
    }
    centre /= static_cast<double>(m);
    const double length = glm::length(mean_tangent);
    if (length > 0.0) {
        const glm::vec3 normal(mean_tangent / length);
        for (size_t j = 0; j < m; ++j) {
            const auto strand = std::span(strands.points).subspan(static_cast<size_t>(members[j]) * nc, nc);
            scratch.points[j] = strand_plane_crossing(strand, k, glm::vec3(centre), normal);
            scratch.tangents[j] = normal;
        }
    }
    return fit_cross_section(scratch.points, scratch.tangents, static_cast<float>(radius / static_cast<double>(m)), coverage,
                             scratch.distances);
}

// Mean area of the ellipses fitted to `members` at kAreaSamples control points spread along the
// hair: the cross-section area the level would store, at a fraction of the fitting cost.
double sampled_area(std::span<const int32_t> members, const StrandSet& resampled, const std::vector<glm::vec3>& tangents,
                    size_t nc, float coverage, SectionScratch& scratch) {
    const size_t samples = std::min(kAreaSamples, nc);
    double area = 0.0;
    for (size_t i = 0; i < samples; ++i) {
        const size_t k = std::min(nc - 1, (2 * i + 1) * nc / (2 * samples));
        area += member_section(members, resampled, tangents, nc, k, coverage, scratch).area();
    }
    return area / static_cast<double>(samples);
}

// k-means of `members` into (up to) k non-empty children.
Groups kmeans_split(std::span<const int32_t> members, size_t k, const FeatureRows& rows, uint64_t seed) {
    std::vector<float> local(members.size() * rows.dim);
    for (size_t m = 0; m < members.size(); ++m)
        std::copy_n(rows.row(static_cast<size_t>(members[m])), rows.dim, local.begin() + static_cast<std::ptrdiff_t>(m * rows.dim));
    const FeatureRows local_rows{local, rows.dim};
    const KMeansResult split = kmeans(local_rows, kmeans_plus_plus_seeds(local_rows, k, seed), 100);
    Groups result(split.centres.size() / rows.dim);
    for (size_t m = 0; m < members.size(); ++m) result[static_cast<size_t>(split.assignment[m])].push_back(members[m]);
    std::erase_if(result, [](const std::vector<int32_t>& g) { return g.empty(); });
    return result;
}

struct SplitContext {
    const FeatureRows& rows;
    const StrandSet& resampled;
    const std::vector<glm::vec3>& tangents;
    size_t control_points;
    float coverage;
};

// Splits every hair of a level into the children whose mean cross-section area is closest to
// 1/kLevelAreaRatio of the hair's (Sec. 5.1 step 2). Area does not follow the strand count (a
// child's strands spread across its parent's section at some control points), so k starts at 4
// and grows by the exponent the last try measured, area ~ k^-alpha. A hair whose children
// would average fewer than kFinestHairStrands strands, or that no try shrinks by
// kMinSplitAreaRatio, is kept whole. `area_ratio` is the parents' mean sampled area over the
// children's.
Groups split_level(const Groups& parents, const SplitContext& context, uint64_t seed, std::vector<int32_t>& parent_of,
                   double& area_ratio) {
    std::vector<Groups> children(parents.size());
    std::vector<double> parent_areas(parents.size()), children_areas(parents.size());
    tbb::parallel_for(size_t{0}, parents.size(), [&](size_t h) {
        const std::vector<int32_t>& members = parents[h];
        const auto most = static_cast<size_t>(static_cast<double>(members.size()) / kFinestHairStrands);
        children[h] = {members};
        if (most < 2) return;
        SectionScratch scratch;
        auto area_of = [&](std::span<const int32_t> group) {
            return sampled_area(group, context.resampled, context.tangents, context.control_points, context.coverage, scratch);
        };
        const double parent_area = parent_areas[h] = children_areas[h] = area_of(members);
        double best_miss = std::numeric_limits<double>::infinity();
        size_t k = std::min<size_t>(static_cast<size_t>(kLevelAreaRatio), most);
        for (int attempt = 0; attempt < kSplitAttempts; ++attempt) {
            // A seed per hair and attempt makes the result independent of scheduling.
            Groups split = kmeans_split(members, k, context.rows, seed ^ (0x9E3779B97F4A7C15ull * (3 * h + attempt + 1)));
            double area_sum = 0.0;
            for (const std::vector<int32_t>& child : split) area_sum += area_of(child);
            const double child_area = area_sum / static_cast<double>(split.size());
            const double ratio = child_area > 0.0 ? parent_area / child_area : kLevelAreaRatio;
            const double miss = std::abs(std::log(ratio / kLevelAreaRatio));
            if (miss < best_miss && split.size() > 1 && ratio >= kMinSplitAreaRatio) {
                best_miss = miss;
                children_areas[h] = area_sum;
                children[h] = std::move(split);
            }
            if (ratio >= kLevelAreaRatio / 1.25 || k == most) break;
            const double alpha = std::clamp(std::log(std::max(ratio, 1.01)) / std::log(static_cast<double>(k)), 0.25, 1.0);
            const auto next = static_cast<size_t>(std::ceil(static_cast<double>(k) * std::pow(kLevelAreaRatio / ratio, 1.0 / alpha)));
            k = std::min(most, std::max(next, k + 1));
        }
    });
    Groups flat;
    parent_of.clear();
    double parent_sum = 0.0, children_sum = 0.0;
    for (size_t h = 0; h < children.size(); ++h) {
        parent_sum += parent_areas[h];
        children_sum += children_areas[h];
        for (std::vector<int32_t>& child : children[h]) {
            flat.push_back(std::move(child));
            parent_of.push_back(static_cast<int32_t>(h));
        }
    }
    const double parent_mean = parent_sum / static_cast<double>(parents.size());
    const double children_mean = children_sum / static_cast<double>(flat.size());
    area_ratio = children_mean > 0.0 ? parent_mean / children_mean : 1.0;
    return flat;
}

// Sec. 5.1 step 3 for every hair of a level: the exact cross-sections [hairs * n_c] (member_section).
std::vector<CrossSection> fit_level(const Groups& groups, const StrandSet& resampled, const std::vector<glm::vec3>& tangents,
                                    int control_points, float coverage) {
    const auto nc = static_cast<size_t>(control_points);
    std::vector<CrossSection> sections(groups.size() * nc);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, groups.size()), [&](const tbb::blocked_range<size_t>& range) {
        SectionScratch scratch;
        for (size_t h = range.begin(); h != range.end(); ++h)
            for (size_t k = 0; k < nc; ++k)
                sections[h * nc + k] = member_section(groups[h], resampled, tangents, nc, k, coverage, scratch);
    });
    return sections;
}

CrossSection world_section(const RestSection& rest, const GuideFrame& frame) {
    CrossSection section;
    section.centre = frame.origin + rest.centre_offset;
    section.major_axis = rest.major_axis;
    section.minor_axis = rest.minor_axis;
    section.major_radius = rest.radii.x;
    section.minor_radius = rest.radii.y;
    return section;
}

// Encodes the exact `sections` of thick level l into the asset (`ordered`: the strands in hierarchy
// order, whose members the sections were fitted to). The decoded ellipse's radii grow
// (before rounding up) until it holds as many members as the exact one, so storage never lowers
// coverage; coverage and mean area are then measured on the decoded ellipses.
void store_level(LodAsset& asset, size_t l, const std::vector<CrossSection>& sections, const StrandSet& ordered,
                 const std::vector<GuideFrame>& frames) {
    ThickHairLevel& level = asset.thick_levels[l];
    const auto nc = static_cast<size_t>(asset.control_points);
    const size_t hairs = level.hair_count();
    level.centre_offset.resize(hairs * nc);
    level.major_axis.resize(hairs * nc);
    level.minor_axis.resize(hairs * nc);
    level.radii.resize(hairs * nc);
    std::vector<int64_t> covered(hairs, 0);
    std::vector<double> area(hairs, 0.0);
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        std::vector<glm::vec3> points;
        std::vector<float> scratch;
        for (auto h = static_cast<size_t>(level.cluster_first[c]); h < static_cast<size_t>(level.cluster_first[c + 1]); ++h) {
            const auto first = static_cast<size_t>(level.member_first[h]);
            points.resize(static_cast<size_t>(level.n_total(h)));
            for (size_t k = 0; k < nc; ++k) {
                const CrossSection& exact = sections[h * nc + k];
                // The points the exact section was fitted to (fit_level): the members' crossings of its plane.
                for (size_t j = 0; j < points.size(); ++j)
                    points[j] = glm::length(exact.tangent) > 0.0f
                                    ? strand_plane_crossing(std::span(ordered.points).subspan((first + j) * nc, nc), k, exact.centre, exact.tangent)
                                    : ordered.points[(first + j) * nc + k];
                const GuideFrame& frame = frames[c * nc + k];
                const size_t at = h * nc + k;
                level.centre_offset[at] = asset.offset_boxes[c * nc + k].encode(exact.centre - frame.origin);
                level.major_axis[at] = encode_octahedral(exact.major_axis);
                level.minor_axis[at] = encode_perpendicular(decode_octahedral(level.major_axis[at]), exact.minor_axis);
                CrossSection stored = world_section(asset.section(l, h, k), frame);
                stored.major_radius = exact.major_radius;
                stored.minor_radius = exact.minor_radius;
                const double growth = growth_to_cover(stored, points, static_cast<size_t>(exact.covered), scratch);
                level.radii[at] = {encode_half_up(static_cast<float>(growth * exact.major_radius), asset.radius_exponent),
                                   encode_half_up(static_cast<float>(growth * exact.minor_radius), asset.radius_exponent)};
                stored = world_section(asset.section(l, h, k), frame);
                for (const glm::vec3& p : points) covered[h] += inside_ellipse(stored, p) ? 1 : 0;
                area[h] += stored.area();
            }
        }
    });
    int64_t covered_total = 0;
    double area_total = 0.0;
    for (size_t h = 0; h < hairs; ++h) {
        covered_total += covered[h];
        area_total += area[h];
    }
    level.coverage = static_cast<double>(covered_total) / static_cast<double>(asset.strand_count() * nc);
    level.mean_area = area_total / static_cast<double>(hairs * nc);
}

// The asset's strands at the rest pose as stored (decoded), in hierarchy order: position i is
// curve i. What the stored cross-sections are fitted to, at the build and when read back.
StrandSet decoded_rest_strands(const LodAsset& asset, const std::vector<GuideFrame>& frames) {
    const auto nc = static_cast<size_t>(asset.control_points);
    StrandSet strands;
    strands.points.resize(asset.strand_count() * nc);
    strands.radius.resize(strands.points.size());
    strands.offsets.resize(asset.strand_count() + 1);
    for (size_t i = 0; i < strands.offsets.size(); ++i) strands.offsets[i] = static_cast<int64_t>(i * nc);
    tbb::parallel_for(size_t{0}, asset.cluster_count(), [&](size_t c) {
        const auto [first, end] = asset.cluster_strands(c);
        for (auto i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i) {
            for (size_t k = 0; k < nc; ++k) {
                strands.points[i * nc + k] = frames[c * nc + k].origin + asset.offset_boxes[c * nc + k].decode(asset.strand_offset[i * nc + k]);
                strands.radius[i * nc + k] = decode_half(asset.strand_radius_code(i, k), asset.radius_exponent);
            }
        }
    });
    return strands;
}

void check_coverage(float ellipse_coverage, const std::string& where) {
    if (!(ellipse_coverage > 0.0f && ellipse_coverage <= 1.0f)) throw Error(where + ": ellipse_coverage must be in (0, 1]");
}

void check_options(const LodOptions& options) {
    if (options.guides < 0) throw Error("build_lod: guides must be >= 1 (or 0: automatic), got " + std::to_string(options.guides));
    if (options.levels < kMinLevels || options.levels > kMaxLevels)
        throw Error("build_lod: levels must be in [" + std::to_string(kMinLevels) + ", " + std::to_string(kMaxLevels) +
                    "] (thick levels plus the strands), got " + std::to_string(options.levels));
    if (options.control_points < kMinControlPoints)
        throw Error("build_lod: control_points must be >= " + std::to_string(kMinControlPoints) + ", got " +
                    std::to_string(options.control_points));
    if (options.max_kmeans_iterations < 0) throw Error("build_lod: max_kmeans_iterations must be >= 0");
    if (!(options.kmeans_stop_fraction >= 0.0 && options.kmeans_stop_fraction < 1.0))
        throw Error("build_lod: kmeans_stop_fraction must be in [0, 1)");
    if (options.arc_length_subdivisions < 1) throw Error("build_lod: arc_length_subdivisions must be >= 1");
    check_coverage(options.ellipse_coverage, "build_lod");
}

}  // namespace

int auto_guide_count(size_t strand_count) {
    const size_t wanted = std::clamp<size_t>(strand_count / kStrandsPerGuide, kMinAutoGuides, kMaxAutoGuides);
    return static_cast<int>(std::max<size_t>(1, std::min(wanted, strand_count)));
}

LodAsset build_lod(const StrandSet& strands, const LodOptions& options) {
    check_options(options);
    if (strands.curve_count() == 0) throw Error("build_lod: no strands");
    strands.validate();
    strands.require_float_range("build_lod");
    if (strands.curve_count() > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
        throw Error("build_lod: too many strands");
    if (options.progress != nullptr) {
        if (options.progress->cancel) throw LodBuildCancelled();
        // Steps: resample, k-means, clusters, each finer level, weights, each level's fitting.
        options.progress->total = 4 + (options.levels - 2) + (options.levels - 1);
        options.progress->done = 0;
    }
    Stopwatch watch;
    LodAsset asset;
    asset.control_points = options.control_points;
    const auto nc = static_cast<size_t>(options.control_points);

    const StrandSet resampled = resample_strands(
        strands, {.points_per_curve = options.control_points, .subdivisions_per_segment = options.arc_length_subdivisions});
    asset.timings.resample = watch.lap();
    report_step(options.progress);

    const std::vector<float> features = centred_features(resampled);
    const FeatureRows rows{features, 3 * nc};
    asset.guide_strands = select_guides(rows, options);
    for (int64_t g : asset.guide_strands)
        asset.rest_guides.insert(asset.rest_guides.end(), resampled.curve_points(static_cast<size_t>(g)).begin(),
                                 resampled.curve_points(static_cast<size_t>(g)).end());
    asset.timings.kmeans = watch.lap();
    report_step(options.progress);

    // L0: strands sharing a guide set; clusters numbered in the sets' lexicographic order.
    const std::vector<std::array<int32_t, 3>> sets = nearest_guide_sets(rows, asset.guide_strands);
    std::map<std::array<int32_t, 3>, int32_t> cluster_of_set;
    for (const auto& set : sets) cluster_of_set.emplace(set, 0);
    for (auto& [set, cluster] : cluster_of_set) {
        cluster = static_cast<int32_t>(asset.cluster_guides.size());
        asset.cluster_guides.push_back(set);
    }
    const size_t strand_count = resampled.curve_count(), cluster_count = asset.cluster_guides.size();
    std::vector<int32_t> strand_cluster(strand_count);
    for (size_t s = 0; s < strand_count; ++s) strand_cluster[s] = cluster_of_set[sets[s]];
    const ClusterMembers l0 = group_by_cluster(strand_cluster, cluster_count);
    asset.timings.clusters = watch.lap();
    report_step(options.progress);

    // Finer levels by splitting L0 (Sec. 5.1 step 2).
    const std::vector<glm::vec3> tangents = unit_tangents(resampled, options.control_points);
    std::vector<Groups> level_groups(1);
    std::vector<std::vector<int32_t>> level_parents(1, std::vector<int32_t>(cluster_count, -1));
    for (size_t c = 0; c < cluster_count; ++c)
        level_groups[0].emplace_back(l0.members.begin() + l0.first[c], l0.members.begin() + l0.first[c + 1]);
    const SplitContext split_context{rows, resampled, tangents, nc, options.ellipse_coverage};
    for (int depth = 1; depth < options.levels - 1; ++depth) {
        std::vector<int32_t> parents;
        double area_ratio = 1.0;
        Groups finer = split_level(level_groups.back(), split_context, options.seed + static_cast<uint64_t>(depth), parents, area_ratio);
        report_step(options.progress);
        if (area_ratio < kMinLevelAreaRatio) break;
        level_groups.push_back(std::move(finer));
        level_parents.push_back(std::move(parents));
    }
    asset.timings.levels = watch.lap();

    // Hierarchy order: the finest level's hairs one after another. Splits keep a parent's children
    // adjacent and in parent order, so every coarser hair is a contiguous range as well.
    for (const std::vector<int32_t>& group : level_groups.back())
        asset.strand_order.insert(asset.strand_order.end(), group.begin(), group.end());

    // Sec. 5.1 step 4: the frame of each L0 cluster's guides per control point. Strand control
    // points and thick-hair centres keep their offset from its rest origin, quantised in the
    // cluster's box; skinning maps the offset by deformed axes x rest axes^-1, which equals the
    // deformed axes applied to the prism coordinates rest axes^-1 x offset.
    asset.frame_kinds.resize(cluster_count * nc);
    tbb::parallel_for(size_t{0}, cluster_count, [&](size_t c) {
        const GuideSet guides = guide_set(asset.cluster_guides[c], asset.rest_guides.data(), options.control_points);
        for (size_t k = 0; k < nc; ++k) asset.frame_kinds[c * nc + k] = choose_frame_kind(guides, static_cast<int>(k));
    });
    const std::vector<GuideFrame> frames = rest_frames(asset);
    asset.offset_boxes.resize(cluster_count * nc);
    asset.strand_offset.resize(strand_count * nc);
    tbb::parallel_for(size_t{0}, cluster_count, [&](size_t c) {
        const auto first = static_cast<size_t>(l0.first[c]), count = static_cast<size_t>(l0.first[c + 1]) - first;
        std::vector<glm::vec3> offset(count);
        for (size_t k = 0; k < nc; ++k) {
            for (size_t j = 0; j < count; ++j) {
                const auto s = static_cast<size_t>(asset.strand_order[first + j]);
                offset[j] = resampled.points[s * nc + k] - frames[c * nc + k].origin;
            }
            const QuantisationBox& box = asset.offset_boxes[c * nc + k] = QuantisationBox::enclosing(offset);
            for (size_t j = 0; j < count; ++j) asset.strand_offset[(first + j) * nc + k] = box.encode(offset[j]);
        }
    });
    asset.timings.weights = watch.lap();
    report_step(options.progress);

    float largest_radius = 0.0f;
    for (size_t l = 0; l < level_groups.size(); ++l) {
        ThickHairLevel& level = asset.thick_levels.emplace_back();
        const Groups& groups = level_groups[l];
        level.parent = std::move(level_parents[l]);
        level.member_first.assign(1, 0);
        level.cluster_first.assign(cluster_count + 1, 0);
        for (size_t h = 0; h < groups.size(); ++h) {
            level.member_first.push_back(level.member_first.back() + static_cast<int32_t>(groups[h].size()));
            ++level.cluster_first[static_cast<size_t>(strand_cluster[static_cast<size_t>(groups[h][0])]) + 1];
        }
        for (size_t c = 0; c < cluster_count; ++c) level.cluster_first[c + 1] += level.cluster_first[c];
        // The exact sections only size the radius codes: those stored are fitted again to the strands
        // as stored (fit_sections), which the asset read back from a file can do as well.
        for (const CrossSection& section : fit_level(groups, resampled, tangents, options.control_points, options.ellipse_coverage))
            largest_radius = std::max({largest_radius, section.major_radius, section.minor_radius});
        report_step(options.progress);
    }
    for (float r : resampled.radius) largest_radius = std::max(largest_radius, r);
    std::frexp(largest_radius, &asset.radius_exponent);
    asset.radius_exponent -= kRadiusHeadroomBits;
    asset.strand_radius.resize(strand_count * nc);
    tbb::parallel_for(size_t{0}, strand_count, [&](size_t i) {
        const auto s = static_cast<size_t>(asset.strand_order[i]);
        for (size_t k = 0; k < nc; ++k) asset.strand_radius[i * nc + k] = encode_half_up(resampled.radius[s * nc + k], asset.radius_exponent);
    });
    // One code per strand where that loses nothing: 2 bytes a strand instead of 2 n_c.
    bool constant_along = true;
    for (size_t i = 0; i < strand_count && constant_along; ++i)
        for (size_t k = 1; k < nc && constant_along; ++k) constant_along = asset.strand_radius[i * nc + k] == asset.strand_radius[i * nc];
    if (constant_along) {
        for (size_t i = 0; i < strand_count; ++i) asset.strand_radius[i] = asset.strand_radius[i * nc];
        asset.strand_radius.resize(strand_count);
        asset.strand_radius.shrink_to_fit();
    }
    asset.ellipse_coverage = options.ellipse_coverage;
    fit_sections(asset);
    asset.timings.fitting = watch.lap();
    if (options.progress != nullptr) options.progress->done = options.progress->total.load();
    return asset;
}

void fit_sections(LodAsset& asset) {
    check_coverage(asset.ellipse_coverage, "LoD asset");
    const std::vector<GuideFrame> frames = rest_frames(asset);
    const StrandSet ordered = decoded_rest_strands(asset, frames);
    const std::vector<glm::vec3> tangents = unit_tangents(ordered, asset.control_points);
    for (size_t l = 0; l < asset.thick_levels.size(); ++l) {
        const ThickHairLevel& level = asset.thick_levels[l];
        Groups groups(level.hair_count());
        for (size_t h = 0; h < groups.size(); ++h) {
            groups[h].resize(static_cast<size_t>(level.n_total(h)));
            std::iota(groups[h].begin(), groups[h].end(), level.member_first[h]);
        }
        store_level(asset, l, fit_level(groups, ordered, tangents, asset.control_points, asset.ellipse_coverage), ordered, frames);
    }
}

std::vector<int32_t> LodAsset::strand_hairs(size_t level) const {
    const ThickHairLevel& thick = thick_levels.at(level);
    std::vector<int32_t> hairs(strand_order.size());
    for (size_t h = 0; h < thick.hair_count(); ++h)
        for (int32_t i = thick.member_first[h]; i < thick.member_first[h + 1]; ++i)
            hairs[static_cast<size_t>(strand_order[static_cast<size_t>(i)])] = static_cast<int32_t>(h);
    return hairs;
}

RestSection LodAsset::section(size_t level, size_t hair, size_t k) const {
    const ThickHairLevel& thick = thick_levels[level];
    const auto nc = static_cast<size_t>(control_points), at = hair * nc + k;
    const auto cluster = static_cast<size_t>(
        std::upper_bound(thick.cluster_first.begin(), thick.cluster_first.end(), static_cast<int32_t>(hair)) -
        thick.cluster_first.begin() - 1);
    RestSection section;
    section.centre_offset = offset_boxes[cluster * nc + k].decode(thick.centre_offset[at]);
    section.major_axis = decode_octahedral(thick.major_axis[at]);
    section.minor_axis = decode_perpendicular(section.major_axis, thick.minor_axis[at]);
    section.radii = {decode_half(thick.radii[at].x, radius_exponent), decode_half(thick.radii[at].y, radius_exponent)};
    return section;
}

std::vector<float> LodAsset::density(size_t level) const {
    const ThickHairLevel& thick = thick_levels.at(level);
    const auto nc = static_cast<size_t>(control_points);
    std::vector<float> rho(thick.hair_count() * nc);
    tbb::parallel_for(size_t{0}, thick.hair_count(), [&](size_t h) {
        for (size_t k = 0; k < nc; ++k) {
            double radius_sum = 0.0;
            for (auto i = static_cast<size_t>(thick.member_first[h]); i < static_cast<size_t>(thick.member_first[h + 1]); ++i)
                radius_sum += decode_half(strand_radius_code(i, k), radius_exponent);
            const double n_total = thick.n_total(h), mean_radius = radius_sum / n_total;
            const glm::vec2 radii = section(level, h, k).radii;
            const double axes_product = static_cast<double>(radii.x) * radii.y;
            // hair-lod-aggregated-bcsdf.txt Sec. 4: rho = n_total r^2 / (|r_A| |r_B|).
            rho[h * nc + k] = axes_product > 0.0 ? static_cast<float>(n_total * mean_radius * mean_radius / axes_product) : 0.0f;
        }
    });
    return rho;
}

size_t LodAsset::memory_bytes() const {
    size_t total = stored_bytes();
    auto add = [&](const char*, const auto& array) { total += array.size() * sizeof(array[0]); };
    for (const ThickHairLevel& level : thick_levels) ThickHairLevel::visit_section_arrays(level, add);
    return total;
}

size_t LodAsset::stored_bytes() const {
    size_t total = sizeof(control_points) + sizeof(radius_exponent) + sizeof(ellipse_coverage) + sizeof(timings);
    auto add = [&](const char*, const auto& array) { total += array.size() * sizeof(array[0]); };
    visit_arrays(*this, add);
    for (const ThickHairLevel& level : thick_levels) {
        ThickHairLevel::visit_hierarchy_arrays(level, add);
        total += sizeof(level.coverage) + sizeof(level.mean_area);
    }
    return total;
}

namespace {

void require(bool condition, const std::string& what) {
    if (!condition) throw Error("LoD asset: " + what);
}

template <typename T>
void require_size(const std::vector<T>& array, size_t expected, const std::string& name) {
    require(array.size() == expected, name + " has " + std::to_string(array.size()) + " entries, expected " +
                                          std::to_string(expected));
}

// Offsets [parts + 1] starting at 0, non-decreasing, ending at `total`.
void require_offsets(const std::vector<int32_t>& first, size_t parts, size_t total, const std::string& name) {
    require_size(first, parts + 1, name);
    require(first.front() == 0 && static_cast<size_t>(first.back()) == total, name + " must run from 0 to " + std::to_string(total));
    require(std::is_sorted(first.begin(), first.end()), name + " must not decrease");
}

template <typename T>
void require_indices(const std::vector<T>& indices, int64_t lowest, size_t count, const std::string& name) {
    for (const T& index : indices)
        require(static_cast<int64_t>(index) >= lowest && static_cast<int64_t>(index) < static_cast<int64_t>(count),
                name + " holds an index outside [" + std::to_string(lowest) + ", " + std::to_string(count) + ")");
}

// Whether a radius code decodes to a finite radius >= 0 (what skinning and shading may read).
bool finite_radius(uint16_t code, int radius_exponent) {
    const float radius = decode_half(code, radius_exponent);
    return std::isfinite(radius) && radius >= 0.0f;
}

}  // namespace

void LodAsset::validate() const {
    validate_structure();
    const auto nc = static_cast<size_t>(control_points);
    for (size_t l = 0; l < thick_levels.size(); ++l) {
        const ThickHairLevel& level = thick_levels[l];
        const std::string name = "level " + std::to_string(l) + " ";
        const size_t hairs = level.hair_count();
        ThickHairLevel::visit_section_arrays(level, [&](const char* array, const auto& values) {
            require(values.size() == hairs * nc, name + array + " must hold n_c entries per hair");
        });
        for (const glm::u16vec2& code : level.radii)
            require(finite_radius(code.x, radius_exponent) && finite_radius(code.y, radius_exponent), name + "radii holds a radius that is not finite");
    }
}

void LodAsset::validate_structure() const {
    require(control_points >= 2, "control_points must be >= 2");
    const auto nc = static_cast<size_t>(control_points);
    require(!strand_order.empty(), "needs at least one strand");
    // Within this range every decoded half stays finite or becomes 0 / inf, never undefined.
    require(radius_exponent >= -200 && radius_exponent <= 200, "radius_exponent must be in [-200, 200]");
    const size_t strands = strand_count(), guides = guide_count(), clusters = cluster_count();
    require(guides > 0 && clusters > 0, "needs at least one guide and one cluster");
    require_size(rest_guides, guides * nc, "rest_guides");
    require_indices(guide_strands, 0, strands, "guide_strands");
    for (const auto& set : cluster_guides) {
        require(set[0] >= 0, "cluster_guides: every cluster needs a guide");
        for (int32_t g : set) require(g >= -1 && g < static_cast<int32_t>(guides), "cluster_guides holds an unknown guide");
    }
    require_size(frame_kinds, clusters * nc, "frame_kinds");
    for (FrameKind kind : frame_kinds) require(kind <= FrameKind::World, "frame_kinds holds an unknown kind");
    require_size(offset_boxes, clusters * nc, "offset_boxes");
    require_size(strand_offset, strands * nc, "strand_offset");
    require(strand_radius.size() == strands * nc || strand_radius.size() == strands,
            "strand_radius has " + std::to_string(strand_radius.size()) + " entries, expected " + std::to_string(strands * nc) +
                " (per control point) or " + std::to_string(strands) + " (per strand)");
    // A stored asset (a file, a pack in a .blend) may be damaged: every value skinning decodes
    // must be finite, or the strands and thick hairs come out NaN without an error.
    const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (const glm::vec3& p : rest_guides) require(finite(p), "rest_guides holds a coordinate that is not finite");
    for (const QuantisationBox& box : offset_boxes)
        require(finite(box.lower) && finite(box.step) && glm::all(glm::greaterThanEqual(box.step, glm::vec3(0.0f))) &&
                    finite(box.decode(glm::u16vec3(std::numeric_limits<uint16_t>::max()))),
                "offset_boxes holds a box that is not finite (or has a negative step)");
    for (uint16_t code : strand_radius) require(finite_radius(code, radius_exponent), "strand_radius holds a radius that is not finite");
    require_size(strand_order, strands, "strand_order");
    require_indices(strand_order, 0, strands, "strand_order");
    std::vector<bool> seen(strands, false);
    for (int32_t s : strand_order) {
        require(!seen[static_cast<size_t>(s)], "strand_order must list every strand once");
        seen[static_cast<size_t>(s)] = true;
    }
    require(!thick_levels.empty() && thick_levels[0].hair_count() == clusters, "level 0 needs one hair per cluster");
    for (size_t l = 0; l < thick_levels.size(); ++l) {
        const ThickHairLevel& level = thick_levels[l];
        const std::string name = "level " + std::to_string(l) + " ";
        const size_t hairs = level.hair_count();
        require_offsets(level.cluster_first, clusters, hairs, name + "cluster_first");
        require_size(level.parent, hairs, name + "parent");
        require_indices(level.parent, l == 0 ? -1 : 0, l == 0 ? 0 : thick_levels[l - 1].hair_count(), name + "parent");
        require_offsets(level.member_first, hairs, strands, name + "member_first");
        for (size_t h = 0; h < hairs; ++h) {
            require(level.n_total(h) > 0, name + "member_first gives a hair no strands");
            if (l == 0) continue;
            const ThickHairLevel& coarser = thick_levels[l - 1];
            const auto p = static_cast<size_t>(level.parent[h]);
            require(coarser.member_first[p] <= level.member_first[h] && level.member_first[h + 1] <= coarser.member_first[p + 1],
                    name + "member_first puts a hair's strands outside its parent");
        }
    }
}

LodAsset LodAsset::with_levels(std::span<const size_t> kept) const {
    if (kept.empty() || kept.back() >= thick_levels.size())
        throw Error("levels to keep must be a non-empty subset of 0.." + std::to_string(thick_levels.size()) + " - 1");
    for (size_t i = 1; i < kept.size(); ++i)
        if (kept[i] <= kept[i - 1]) throw Error("levels to keep must be strictly increasing");
    LodAsset result = *this;
    result.thick_levels.clear();
    for (size_t i = 0; i < kept.size(); ++i) {
        ThickHairLevel level = thick_levels[kept[i]];
        if (i == 0) {
            std::fill(level.parent.begin(), level.parent.end(), -1);
        } else {
            // Follow the parents up through the levels dropped between this one and the last kept.
            for (size_t between = kept[i] - 1; between > kept[i - 1]; --between)
                for (int32_t& parent : level.parent) parent = thick_levels[between].parent[static_cast<size_t>(parent)];
        }
        result.thick_levels.push_back(std::move(level));
    }
    return result;
}

}  // namespace hairlod
