#include "hairlod/curves/surface_attachment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "hairlod/core/error.h"

namespace hairlod {
namespace {

// A grid of n x n quads over [0, 1]^2 in UV, each cut into two triangles; in space a bumpy sheet
// z = 0.2 sin(3x) cos(2y), with the corners' normals of the sheet (smooth shading).
struct Sheet {
    int n = 0;
    std::vector<glm::vec3> positions, corner_normals;
    std::vector<int32_t> corner_verts;
    std::vector<glm::vec2> corner_uvs;
    std::vector<glm::ivec3> triangles;

    SurfaceMesh mesh() const { return {positions, corner_verts, triangles, corner_normals}; }
};

glm::vec3 sheet_normal(float x, float y) {
    return glm::normalize(glm::vec3(-0.6f * std::cos(3.0f * x) * std::cos(2.0f * y), 0.4f * std::sin(3.0f * x) * std::sin(2.0f * y), 1.0f));
}

Sheet make_sheet(int n) {
    Sheet s;
    s.n = n;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = static_cast<float>(i) / static_cast<float>(n), y = static_cast<float>(j) / static_cast<float>(n);
            s.positions.emplace_back(x, y, 0.2f * std::sin(3.0f * x) * std::cos(2.0f * y));
        }
    auto vertex = [n](int i, int j) { return j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int quad[2][3] = {{vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)},
                                    {vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)}};
            for (const auto& tri : quad) {
                glm::ivec3 corners;
                for (int k = 0; k < 3; ++k) {
                    corners[k] = static_cast<int32_t>(s.corner_verts.size());
                    s.corner_verts.push_back(tri[k]);
                    const glm::vec3 p = s.positions[static_cast<size_t>(tri[k])];
                    s.corner_uvs.emplace_back(p.x, p.y);
                    s.corner_normals.push_back(sheet_normal(p.x, p.y));
                }
                s.triangles.push_back(corners);
            }
        }
    return s;
}

// The sheet moved by `move` (positions) with its normals turned by the inverse transpose.
Sheet moved(const Sheet& rest, const glm::mat4& move) {
    Sheet s = rest;
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(move)));
    for (glm::vec3& p : s.positions) p = glm::vec3(move * glm::vec4(p, 1.0f));
    for (glm::vec3& v : s.corner_normals) v = glm::normalize(normal_matrix * v);
    return s;
}

// Blender's transform of a curve from the original mesh to a deformed one, written out as the node
// documents it (double precision): the frames of the root point on both, p' = R' R^T (p - o) + o'.
glm::dvec3 deform_point(const Sheet& original, const Sheet& deformed, int32_t triangle, const glm::vec3& w, const glm::dvec3& p) {
    auto frame = [&](const Sheet& s, glm::dmat3& rotation, glm::dvec3& origin) {
        const glm::ivec3 c = s.triangles[static_cast<size_t>(triangle)];
        glm::dvec3 normal(0.0), position[3];
        origin = glm::dvec3(0.0);
        for (int k = 0; k < 3; ++k) {
            position[k] = s.positions[static_cast<size_t>(s.corner_verts[static_cast<size_t>(c[k])])];
            normal += double(w[k]) * glm::dvec3(s.corner_normals[static_cast<size_t>(c[k])]);
            origin += double(w[k]) * position[k];
        }
        normal = glm::normalize(normal);
        const glm::dvec3 x = glm::normalize(glm::cross(normal, position[1] - position[0]));
        rotation = glm::dmat3(x, glm::normalize(glm::cross(normal, x)), normal);
    };
    glm::dmat3 r0, r1;
    glm::dvec3 o0, o1;
    frame(original, r0, o0);
    frame(deformed, r1, o1);
    return r1 * glm::transpose(r0) * (p - o0) + o1;
}

glm::vec3 apply(const std::vector<glm::vec4>& rows, size_t curve, const glm::vec3& p) {
    const glm::vec4 q(p, 1.0f);
    return {glm::dot(rows[3 * curve], q), glm::dot(rows[3 * curve + 1], q), glm::dot(rows[3 * curve + 2], q)};
}

TEST(SurfaceAttachment, BindsEachUvToTheTriangleHoldingIt) {
    const Sheet sheet = make_sheet(4);
    // Inside the triangle below the diagonal of quad (1, 2) (triangle 2 (2 n + 1)), the one above it in
    // quad (3, 0) (2 (0 n + 3) + 1), on the diagonal shared by quad (0, 0)'s two triangles, and outside
    // the map (near it, not a number, far beyond an int's range).
    const std::vector<glm::vec2> uvs = {{0.30f, 0.52f}, {0.80f, 0.20f}, {0.125f, 0.125f}, {1.5f, 0.5f}, {NAN, 0.5f},
                                           {1e30f, -1e30f}};
    const SurfaceBinding b = bind_by_uv(uvs, sheet.corner_uvs, sheet.triangles);
    ASSERT_EQ(b.triangle.size(), uvs.size());
    EXPECT_EQ(b.triangle[0], 2 * (2 * 4 + 1));
    EXPECT_EQ(b.triangle[1], 2 * (0 * 4 + 3) + 1);
    EXPECT_TRUE(b.triangle[2] == 0 || b.triangle[2] == 1);
    EXPECT_EQ(b.triangle[3], -1);
    EXPECT_EQ(b.triangle[4], -1);
    EXPECT_EQ(b.triangle[5], -1);
    for (size_t i = 0; i < 3; ++i) {
        // The weights rebuild the UV coordinate from the triangle's corners.
        const glm::ivec3 c = sheet.triangles[static_cast<size_t>(b.triangle[i])];
        const glm::vec2 rebuilt = b.weights[i].x * sheet.corner_uvs[static_cast<size_t>(c.x)] +
                                  b.weights[i].y * sheet.corner_uvs[static_cast<size_t>(c.y)] +
                                  b.weights[i].z * sheet.corner_uvs[static_cast<size_t>(c.z)];
        EXPECT_NEAR(rebuilt.x, uvs[i].x, 1e-6f);
        EXPECT_NEAR(rebuilt.y, uvs[i].y, 1e-6f);
    }
}

TEST(SurfaceAttachment, AUvWellInsideTwoTrianglesIsAmbiguous) {
    Sheet sheet = make_sheet(2);
    // A copy of the first triangle's UVs over the last one's: an overlapping UV map.
    const glm::ivec3 first = sheet.triangles.front(), last = sheet.triangles.back();
    for (int k = 0; k < 3; ++k) sheet.corner_uvs[static_cast<size_t>(last[k])] = sheet.corner_uvs[static_cast<size_t>(first[k])];
    const std::vector<glm::vec2> uvs = {{0.3f, 0.1f}, {0.9f, 0.6f}};
    const SurfaceBinding b = bind_by_uv(uvs, sheet.corner_uvs, sheet.triangles);
    EXPECT_EQ(b.triangle[0], -1);
    EXPECT_GE(b.triangle[1], 0);
}

std::vector<glm::vec2> random_uvs(size_t count, uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(0.02f, 0.98f);
    std::vector<glm::vec2> uvs(count);
    for (glm::vec2& uv : uvs) uv = {unit(random), unit(random)};
    return uvs;
}

TEST(SurfaceAttachment, ARigidMotionOfTheSurfaceMovesEveryCurveRigidly) {
    const Sheet rest = make_sheet(8);
    const std::vector<glm::vec2> uvs = random_uvs(500, 1);
    const glm::mat4 motion = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -1.0f, 2.0f)), 0.7f, glm::vec3(1.0f, 2.0f, 0.5f));
    // The surface object lies elsewhere than the curves object: a fixed matrix between them.
    const glm::mat4 surface_to_curves = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(-2.0f, 0.0f, 1.0f)), glm::vec3(1.5f));
    SurfaceFollow follow(bind_by_uv(uvs, rest.corner_uvs, rest.triangles), rest.mesh(), surface_to_curves);
    EXPECT_EQ(follow.bound_count(), uvs.size());
    const Sheet posed = moved(rest, motion);
    const std::vector<glm::vec4> rows = follow.transforms(posed.positions, posed.corner_normals, surface_to_curves);
    // In the curves' space the motion is surface_to_curves x motion x its inverse, for every curve.
    const glm::mat4 expected = surface_to_curves * motion * glm::inverse(surface_to_curves);
    const std::vector<glm::vec3> probes = {{0.0f, 0.0f, 0.0f}, {1.0f, -2.0f, 3.0f}, {-4.0f, 0.5f, 0.25f}};
    for (size_t i = 0; i < uvs.size(); ++i)
        for (const glm::vec3& p : probes) {
            const glm::vec3 got = apply(rows, i, p), want = glm::vec3(expected * glm::vec4(p, 1.0f));
            ASSERT_LT(glm::length(got - want), 2e-5f) << "curve " << i;
        }
}

TEST(SurfaceAttachment, FollowsBlendersDeformationOfASheardSurfaceFromAnyRestPose) {
    // The curves' rest pose is the surface already deformed once (an LoD built at a later frame);
    // the transform to a second deformation must equal Blender's from the original to the second,
    // applied to the curve as Blender placed it at the first.
    const Sheet original = make_sheet(6);
    Sheet first = original, second = original;
    for (size_t v = 0; v < original.positions.size(); ++v) {
        const glm::vec3 p = original.positions[v];
        first.positions[v] = p + glm::vec3(0.3f * p.y * p.y, 0.0f, 0.1f * p.x);           // shear and bend
        second.positions[v] = p + glm::vec3(-0.2f * p.y, 0.5f * p.x * p.x, 0.3f * p.x * p.y);
    }
    // Normals as a mesh would have them: the deformed sheet's normals at the corners, by the
    // Jacobian of each deformation (inverse transpose).
    auto deform_normals = [&](Sheet& s, auto jacobian) {
        for (size_t c = 0; c < s.corner_verts.size(); ++c) {
            const glm::vec3 p = original.positions[static_cast<size_t>(s.corner_verts[c])];
            s.corner_normals[c] = glm::normalize(glm::transpose(glm::inverse(jacobian(p))) * original.corner_normals[c]);
        }
    };
    deform_normals(first, [](const glm::vec3& p) { return glm::mat3(glm::vec3(1, 0, 0.1f), glm::vec3(0.6f * p.y, 1, 0), glm::vec3(0, 0, 1)); });
    deform_normals(second, [](const glm::vec3& p) {
        return glm::mat3(glm::vec3(1, p.x, 0.3f * p.y), glm::vec3(-0.2f, 1, 0.3f * p.x), glm::vec3(0, 0, 1));
    });
    const std::vector<glm::vec2> uvs = random_uvs(400, 7);
    const SurfaceBinding binding = bind_by_uv(uvs, original.corner_uvs, original.triangles);
    const glm::mat4 identity(1.0f);
    SurfaceFollow follow(binding, first.mesh(), identity);
    const std::vector<glm::vec4> rows = follow.transforms(second.positions, second.corner_normals, identity);
    std::mt19937 random(3);
    std::uniform_real_distribution<float> offset(-0.3f, 0.3f);
    double largest = 0.0;
    for (size_t i = 0; i < uvs.size(); ++i) {
        ASSERT_GE(binding.triangle[i], 0);
        // A point of the curve in the original pose (near its root), where Blender put it at the first
        // deformation, and where at the second.
        const glm::dvec3 p(uvs[i].x + offset(random), uvs[i].y + offset(random), 0.2 + offset(random));
        const glm::dvec3 at_first = deform_point(original, first, binding.triangle[i], binding.weights[i], p);
        const glm::dvec3 at_second = deform_point(original, second, binding.triangle[i], binding.weights[i], p);
        largest = std::max(largest, glm::length(glm::dvec3(apply(rows, i, glm::vec3(at_first))) - at_second));
    }
    EXPECT_LT(largest, 2e-6);
}

TEST(SurfaceAttachment, DegenerateFramesKeepTheirCurvesAndBadIndicesAreErrors) {
    Sheet rest = make_sheet(2);
    const std::vector<glm::vec2> uvs = {{0.3f, 0.1f}, {0.9f, 0.6f}};
    const SurfaceBinding binding = bind_by_uv(uvs, rest.corner_uvs, rest.triangles);
    // The first curve's triangle loses its normals: no frame at rest, it stays where it is.
    for (int k = 0; k < 3; ++k) rest.corner_normals[static_cast<size_t>(rest.triangles[static_cast<size_t>(binding.triangle[0])][k])] = glm::vec3(0.0f);
    const glm::mat4 identity(1.0f);
    SurfaceFollow follow(binding, rest.mesh(), identity);
    EXPECT_FALSE(follow.is_bound(0));
    EXPECT_TRUE(follow.is_bound(1));
    const Sheet posed = moved(rest, glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, 3.0f)));
    const std::vector<glm::vec4> rows = follow.transforms(posed.positions, posed.corner_normals, identity);
    EXPECT_EQ(apply(rows, 0, glm::vec3(0.5f)), glm::vec3(0.5f));
    EXPECT_LT(glm::length(apply(rows, 1, glm::vec3(0.5f)) - glm::vec3(1.5f, 2.5f, 3.5f)), 1e-5f);
    // Written into rows the caller keeps (the preview's, from pose to pose): every entry, the unbound
    // curve's identity too, whatever they held; rows of another length are an error.
    std::vector<glm::vec4> kept(6, glm::vec4(std::numeric_limits<float>::quiet_NaN()));
    follow.transforms(posed.positions, posed.corner_normals, identity, kept);
    EXPECT_EQ(kept, rows);
    std::vector<glm::vec4> short_rows(5);
    EXPECT_THROW(follow.transforms(posed.positions, posed.corner_normals, identity, short_rows), Error);
    // A pose with another vertex or corner count, a rest mesh whose corner names a missing vertex, a
    // singular matrix.
    std::vector<glm::vec3> fewer(posed.positions.begin(), posed.positions.end() - 1);
    EXPECT_THROW(follow.transforms(fewer, posed.corner_normals, identity), Error);
    EXPECT_THROW(follow.transforms(posed.positions, fewer, identity), Error);
    Sheet broken = rest;
    broken.corner_verts[4] = 1000;
    EXPECT_THROW(SurfaceFollow(binding, broken.mesh(), identity), Error);
    EXPECT_THROW(SurfaceFollow(binding, rest.mesh(), glm::mat4(0.0f)), Error);
    std::vector<glm::ivec3> bad = rest.triangles;
    bad[0].y = 99;
    EXPECT_THROW(bind_by_uv(uvs, rest.corner_uvs, bad), Error);
}

}  // namespace
}  // namespace hairlod
