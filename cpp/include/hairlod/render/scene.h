#pragma once
// The Embree scene (3 or 4, render/embree.h) of the reference renderer: strands as round Catmull-Rom curves with per-point
// radius, and LoD thick hairs as round curves of radius = the major radius whose hits are kept only
// where the ray crosses the elliptical cross-section (hair-lod-aggregated-bcsdf.txt Sec. 4, the ray
// length through the ellipse gives the hair count n). Vertex and index buffers are owned here and
// shared with Embree (no copies).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "hairlod/core/strand_set.h"
#include "hairlod/render/embree.h"

namespace hairlod::render {

// An Embree device whose errors (reported through the error callback) are thrown as hairlod::Error
// by check().
class Device {
public:
    Device();
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;
    RTCDevice get() const { return device_; }
    // Throws hairlod::Error with the first error Embree reported since the last check, naming `what`.
    void check(const char* what);

private:
    RTCDevice device_ = nullptr;
    std::string error_;
};

// Thick hairs of an LoD selection: curves of control points (centre curve) with per-point
// cross-sections; per-point arrays have offsets.back() entries.
struct ThickHairs {
    std::vector<glm::vec3> centres;
    std::vector<int64_t> offsets{0};
    std::vector<glm::vec3> major_axis;  // unit
    std::vector<glm::vec2> radii;       // (major, minor), major >= minor > 0
    std::vector<float> density;         // rho in (0, 1] (Sec. 4)
    std::vector<float> n_total;         // per hair: member strands
    // Throws hairlod::Error naming the first inconsistent array or value.
    void validate() const;
};

enum class CurveKind : uint8_t { Strand, Thick };

// Where a ray hit a curve, in world space, with the frame the BCSDFs need.
struct SurfaceHit {
    float t = 0.0f;
    glm::vec3 position{0.0f};
    glm::vec3 tangent{1.0f, 0.0f, 0.0f};  // unit, along the curve
    glm::vec3 normal{0.0f, 0.0f, 1.0f};   // unit geometric normal of the tube
    float radius = 0.0f;                  // tube radius at the hit
    CurveKind kind = CurveKind::Strand;
    unsigned geometry = RTC_INVALID_GEOMETRY_ID;
    uint32_t curve = 0;
    // Thick hairs: the chord length through the ellipse along the ray, n_total and rho there.
    float chord = 0.0f;
    float n_total = 1.0f;
    float density = 1.0f;
    glm::vec2 radii{0.0f};
    // Thick hairs: the strands the ray would meet on average past the hit, to the hair's far side, and
    // the in-plane length of the ray inside the hair before the hit (a corridor the ray found empty).
    float strands_behind = 0.0f;
    float cleared_chord = 0.0f;
};

// A ray's way out of a thick hair from a point inside it: its in-plane length and the strands it meets
// there on average.
struct HairPassage {
    float chord = 0.0f;
    double expected = 0.0;
};

// What a ray leaving a surface must ignore: hits on its own curve closer than `skip_distance`
// (the tube it leaves, including the far side a transmitted ray crosses).
struct RayOrigin {
    unsigned geometry = RTC_INVALID_GEOMETRY_ID;
    uint32_t curve = 0;
    float skip_distance = 0.0f;
};

class HairScene {
public:
    explicit HairScene(std::shared_ptr<Device> device);
    ~HairScene();
    HairScene(const HairScene&) = delete;
    HairScene& operator=(const HairScene&) = delete;

    // Adds strands (validated; radius must be > 0) as one Catmull-Rom geometry; before commit().
    void add_strands(const StrandSet& strands);
    void add_thick_hairs(const ThickHairs& hairs);
    void commit();

    size_t segment_count() const;
    size_t segment_count(CurveKind kind) const;

    // Closest accepted hit along origin + t direction, t in (0, t_max); false if none. A thick hair
    // is hit where the ray meets its first member strand (a Poisson arrival inside the hair, Sec. 4's
    // density), not where it enters the tube.
    bool intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from,
                   SurfaceHit& hit) const;
    // Whether anything is hit in (0, t_max).
    bool occluded(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from) const;
    // Distinct curves crossed in (0, t_max): an occlusion filter counts each hit and rejects it so that
    // traversal continues (dual scattering's forward transmittance). Stops counting at `limit`.
    int count_crossings(const glm::vec3& origin, const glm::vec3& direction, float t_max, const RayOrigin& from,
                        int limit = 64) const;

    // The strands of the hit's own thick hair that a ray from the hit in `direction` meets on average on
    // its way out (0 for strands): the hair shadowing itself, which rays leaving the hit skip.
    HairPassage own_hair_passage(const SurfaceHit& hit, const glm::vec3& direction) const;

    // The strand of the hit's own thick hair that a ray from the hit in `direction` meets at the Poisson
    // arrival `arrival` (expected strands passed, as own_hair_passage counts them): false when the ray
    // leaves the hair first. `next` is then a hit on that strand, in the same hair.
    bool strand_inside(const SurfaceHit& hit, const glm::vec3& direction, double arrival, SurfaceHit& next) const;

    // The origin record of a ray leaving `hit` in `direction`.
    RayOrigin leaving(const SurfaceHit& hit, const glm::vec3& direction) const;

    struct Geometry;     // buffers of one Embree curve geometry (scene.cpp)
    struct FirstStrand;  // where a ray meets a thick hair's first strand (scene.cpp)

private:
    void attach(std::unique_ptr<Geometry> geometry);
    // `inside`: for a thick hair, where the ray meets its first strand and what lies behind (scene.cpp).
    void fill_hit(const Geometry& g, const RTCRayHit& rh, const glm::vec3& origin, const glm::vec3& direction, float t,
                  const FirstStrand& inside, SurfaceHit& hit) const;

    std::shared_ptr<Device> device_;
    RTCScene scene_ = nullptr;
    std::vector<std::unique_ptr<Geometry>> geometries_;  // indexed by Embree geometry id
    bool committed_ = false;
};

}  // namespace hairlod::render
