#include "hairlod/hairmesh/styling_frames.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "hairlod/core/error.h"

namespace hairlod {

namespace {

// A direction sum whose length is below this fraction of the summed lengths has cancelled out.
constexpr double kCancellation = 1e-6;
// Corner triangles whose texture-space area is below this fraction of |e1| |e2| are skipped.
constexpr double kFlatUv = 1e-9;

struct DirectionSum {
    glm::dvec3 u{0.0}, v{0.0};
    double u_scale = 0.0, v_scale = 0.0;

    bool usable() const {
        const double lu = glm::length(u), lv = glm::length(v);
        if (!(lu > kCancellation * u_scale && lv > kCancellation * v_scale)) return false;
        // u and v must span a plane for Bhokare 2024 Eq. 4 to define w.
        return glm::length(glm::cross(u / lu, v / lv)) > kCancellation;
    }
};

// Adds the Bhokare 2024 Eq. 3 directions of one corner triangle (p0 the vertex, p1 next, p2 previous),
// weighted by its texture-space area A_i (Bhokare 2024 Eq. 1).
void add_corner(DirectionSum& sum, const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                const glm::dvec2& uv0, const glm::dvec2& uv1, const glm::dvec2& uv2) {
    // Bhokare 2024 Eq. 2: T_i = [uv1 - uv0, uv2 - uv0] (columns).
    const glm::dvec2 c1 = uv1 - uv0, c2 = uv2 - uv0;
    const double det = c1.x * c2.y - c2.x * c1.y;
    if (!(std::abs(det) > kFlatUv * glm::length(c1) * glm::length(c2))) return;
    // Bhokare 2024 Eq. 3: [u_i v_i] = [p1 - p0, p2 - p0] T_i^-1, with T_i^-1 = [[c2.y, -c2.x], [-c1.y, c1.x]] / det.
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec3 u_i = (e1 * c2.y - e2 * c1.y) / det;
    const glm::dvec3 v_i = (e2 * c1.x - e1 * c2.x) / det;
    const double area = 0.5 * std::abs(det);
    sum.u += area * u_i;
    sum.v += area * v_i;
    sum.u_scale += area * glm::length(u_i);
    sum.v_scale += area * glm::length(v_i);
}

// A frame from object space alone for a root vertex whose uv gives none (a pole where the uv
// directions around it cancel, or uv triangles that all collapse): u the world axis least aligned
// with the normal n, made tangent, and v = n x u, so that w = u x v = n (Bhokare 2024 Eq. 4) points out of the scalp.
void object_space_frame(const glm::dvec3& normal, glm::vec3& u, glm::vec3& v) {
    const glm::dvec3 n = glm::normalize(normal);
    const glm::dvec3 a = std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 axis_u = glm::normalize(a - n * glm::dot(a, n));
    u = glm::vec3(axis_u);
    v = glm::vec3(glm::cross(n, axis_u));
}

}  // namespace

std::vector<glm::vec2> default_root_uv(const HairMesh& mesh) {
    glm::dvec3 normal(0.0), centroid(0.0);
    for (size_t f = 0; f < mesh.face_count(); ++f) {
        const FaceCorners c = mesh.face_corners(f);
        const glm::dvec3 p0(mesh.position(0, c.vertex[0])), p1(mesh.position(0, c.vertex[1])),
            p2(mesh.position(0, c.vertex[2])), p3(mesh.position(0, c.vertex[3]));
        normal += glm::cross(p2 - p0, p3 - p1);
    }
    for (size_t i = 0; i < mesh.vertex_count; ++i) centroid += glm::dvec3(mesh.position(0, i));
    centroid /= static_cast<double>(mesh.vertex_count);
    if (!(glm::length(normal) > 0.0)) throw Error("hair mesh root layer has zero area; give it uv or non-degenerate faces");
    normal = glm::normalize(normal);
    // The world axis least aligned with the normal gives a well-conditioned first tangent axis.
    const glm::dvec3 a = std::abs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 axis_u = glm::normalize(a - normal * glm::dot(a, normal));
    const glm::dvec3 axis_v = glm::cross(normal, axis_u);
    std::vector<glm::vec2> uv(mesh.corner_count());
    for (size_t k = 0; k < uv.size(); ++k) {
        const glm::dvec3 d = glm::dvec3(mesh.position(0, mesh.corner_vertices[k])) - centroid;
        uv[k] = glm::vec2(glm::dot(d, axis_u), glm::dot(d, axis_v));
    }
    return uv;
}

StylingFrames compute_styling_frames(const HairMesh& mesh) {
    StylingFrames frames;
    frames.corner_uv = mesh.corner_uv.empty() ? default_root_uv(mesh) : mesh.corner_uv;
    const size_t vertex_count = mesh.vertex_count, layers = mesh.layer_count();
    frames.u.resize(mesh.positions.size());
    frames.v.resize(mesh.positions.size());

    std::vector<DirectionSum> sums(vertex_count);
    // Area-weighted root-layer normals (twice the corner triangle areas), for object_space_frame.
    std::vector<glm::dvec3> root_normals(vertex_count, glm::dvec3(0.0));
    for (size_t layer = 0; layer < layers; ++layer) {
        std::fill(sums.begin(), sums.end(), DirectionSum{});
        DirectionSum whole_layer;
        for (size_t f = 0; f < mesh.face_count(); ++f) {
            const int32_t first = mesh.face_offsets[f];
            const int32_t n = mesh.face_offsets[f + 1] - first;
            for (int32_t k = 0; k < n; ++k) {
                const int32_t c0 = first + k, c1 = first + (k + 1) % n, c2 = first + (k + n - 1) % n;
                const auto vertex = static_cast<size_t>(mesh.corner_vertices[c0]);
                add_corner(sums[vertex], mesh.position(layer, vertex), mesh.position(layer, mesh.corner_vertices[c1]),
                           mesh.position(layer, mesh.corner_vertices[c2]), frames.corner_uv[c0], frames.corner_uv[c1],
                           frames.corner_uv[c2]);
                if (layer == 0) {
                    const glm::dvec3 p0(mesh.position(0, vertex));
                    root_normals[vertex] += glm::cross(glm::dvec3(mesh.position(0, mesh.corner_vertices[c1])) - p0,
                                                       glm::dvec3(mesh.position(0, mesh.corner_vertices[c2])) - p0);
                    add_corner(whole_layer, mesh.position(0, vertex), mesh.position(0, mesh.corner_vertices[c1]),
                               mesh.position(0, mesh.corner_vertices[c2]), frames.corner_uv[c0],
                               frames.corner_uv[c1], frames.corner_uv[c2]);
                }
            }
        }
        glm::dvec3 layer_normal(0.0);
        if (layer == 0) {
            double area = 0.0;
            for (const glm::dvec3& n : root_normals) {
                layer_normal += n;
                area += glm::length(n);
            }
            if (!(area > 0.0) || !std::isfinite(area)) throw Error("hair mesh root layer has zero area in object space");
            if (!(glm::length(layer_normal) > kCancellation * area)) layer_normal = glm::dvec3(0, 0, 1);
        }
        const bool layer_usable = whole_layer.usable();
        for (size_t i = 0; i < vertex_count; ++i) {
            const size_t at = layer * vertex_count + i;
            // Fallbacks, in order: the layer below; the root layer's mean uv directions; object space.
            if (sums[i].usable() || (layer == 0 && layer_usable)) {
                const DirectionSum& sum = sums[i].usable() ? sums[i] : whole_layer;
                frames.u[at] = glm::vec3(glm::normalize(sum.u));
                frames.v[at] = glm::vec3(glm::normalize(sum.v));
            } else if (layer == 0) {
                object_space_frame(glm::length(root_normals[i]) > 0.0 ? root_normals[i] : layer_normal, frames.u[at],
                                   frames.v[at]);
            } else {
                frames.u[at] = frames.u[at - vertex_count];
                frames.v[at] = frames.v[at - vertex_count];
            }
        }
    }

    if (!mesh.w.empty()) {
        frames.w = mesh.w;
    } else {
        // Sec. 3.4: w = 0 on the root layer, then the path length along the vertex's extrusions.
        frames.w.assign(mesh.positions.size(), 0.0f);
        for (size_t i = 0; i < vertex_count; ++i) {
            double length = 0.0;
            for (size_t layer = 1; layer < layers; ++layer) {
                length += glm::distance(glm::dvec3(mesh.position(layer, i)), glm::dvec3(mesh.position(layer - 1, i)));
                frames.w[layer * vertex_count + i] = static_cast<float>(length);
            }
        }
    }
    return frames;
}

}  // namespace hairlod
