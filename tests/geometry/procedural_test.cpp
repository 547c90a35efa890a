#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/geometry/sphere.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <map>
#include <string>
#include <utility>

using namespace librt;

using librt::testing::error_of;

namespace {

/// The signed volume enclosed, via the divergence theorem: positive when the winding faces
/// outward.
double signed_volume(const TriangleMesh& m) {
    double v = 0.0;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        const Triangle t = m.triangle(i);
        // Volume of the tetrahedron (0, p0, p1, p2): p0 . (p1 x p2) / 6.
        v += glm::dot(glm::dvec3(t.p0), glm::cross(glm::dvec3(t.p1), glm::dvec3(t.p2))) / 6.0;
    }
    return v;
}

double total_area(const TriangleMesh& m) {
    double a = 0.0;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        a += 0.5 * glm::length(glm::dvec3(area_normal(m.triangle(i))));
    }
    return a;
}

/// Every edge used exactly once in each direction: closed, manifold, consistently wound.
bool is_closed_and_consistent(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const glm::uvec3& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
        if (count != 1) return false;
        const auto reverse = directed.find({edge.second, edge.first});
        if (reverse == directed.end() || reverse->second != 1) return false;
    }
    return true;
}

/// Checks unit normals pointing away from `center` and outward winding.
void expect_outward(const TriangleMesh& m, const glm::vec3& center) {
    ASSERT_EQ(m.normals.size(), m.vertex_count());
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        EXPECT_NEAR(glm::length(m.normals[i]), 1.0f, 1e-5f) << "vertex " << i;
        EXPECT_GT(glm::dot(m.normals[i], m.positions[i] - center), 0.0f) << "vertex " << i;
    }
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        const Triangle t = m.triangle(i);
        EXPECT_GT(glm::dot(area_normal(t), centroid(t) - center), 0.0f) << "triangle " << i;
    }
}

}  // namespace

TEST(Procedural, UvSphereVerticesLieOnTheSphere) {
    const glm::vec3 c(1, -2, 3);
    const float r = 2.5f;
    const TriangleMesh m = make_uv_sphere(c, r, 24, 12);
    EXPECT_NO_THROW(validate(m));
    EXPECT_EQ(m.vertex_count(), 25u * 13u);
    EXPECT_EQ(m.triangle_count(), 2u * 24u * 11u);
    for (const glm::vec3& p : m.positions) EXPECT_NEAR(glm::distance(p, c), r, 1e-5f * r);
    expect_outward(m, c);
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        EXPECT_GT(glm::length(area_normal(m.triangle(i))), 0.0f) << "triangle " << i;
    }
    // Area approaches 4 pi r^2 from below (the facets are chords).
    const double sphere_area = 4.0 * glm::pi<double>() * r * r;
    EXPECT_LT(total_area(m), sphere_area);
    EXPECT_GT(total_area(m), 0.98 * sphere_area);
    EXPECT_GT(signed_volume(make_uv_sphere(glm::vec3(0), 1, 8, 4)), 0.0);
}

TEST(Procedural, UvSphereUvsMatchSphereUv) {
    const Sphere s{{0, 1, 0}, 2.0f};
    const TriangleMesh m = make_uv_sphere(s.center, s.radius, 16, 8);
    const std::size_t row = 17;
    for (std::size_t i = 1; i < 8; ++i) {       // poles have no azimuth
        for (std::size_t j = 1; j < 16; ++j) {  // the seam is u = 0 and 1 at once
            const std::size_t k = i * row + j;
            const glm::vec2 expected = sphere_uv(s, m.positions[k]);
            EXPECT_NEAR(m.uvs[k].x, expected.x, 1e-5f) << k;
            EXPECT_NEAR(m.uvs[k].y, expected.y, 1e-5f) << k;
        }
    }
}

TEST(Procedural, IcosphereIsClosedAndOnTheSphere) {
    for (int s = 0; s <= 3; ++s) {
        const glm::vec3 c(0.5f, 0, -1);
        const TriangleMesh m = make_icosphere(c, 3.0f, s);
        const std::size_t f = std::size_t{1} << (2 * s);  // 4^s
        EXPECT_EQ(m.vertex_count(), 10 * f + 2);
        EXPECT_EQ(m.triangle_count(), 20 * f);
        EXPECT_TRUE(m.uvs.empty());
        EXPECT_NO_THROW(validate(m));
        for (const glm::vec3& p : m.positions) EXPECT_NEAR(glm::distance(p, c), 3.0f, 1e-5f);
        expect_outward(m, c);
        EXPECT_TRUE(is_closed_and_consistent(m)) << "subdivisions " << s;
    }
}

TEST(Procedural, QuadFacesItsEdgeCross) {
    const TriangleMesh q = make_quad({1, 2, 3}, {2, 0, 0}, {0, 0, -3});
    EXPECT_EQ(q.triangle_count(), 2u);
    EXPECT_NEAR(total_area(q), 6.0, 1e-6);
    for (const glm::vec3& n : q.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));  // x cross -z = +y
    for (std::size_t i = 0; i < 2; ++i) EXPECT_GT(area_normal(q.triangle(i)).y, 0.0f);
    EXPECT_EQ(q.positions[2], glm::vec3(3, 2, 0));
    EXPECT_EQ(q.uvs[2], glm::vec2(1, 1));
    EXPECT_THROW((void)make_quad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}), Error);
}

TEST(Procedural, BoxIsClosedOutwardAndExact) {
    const glm::vec3 lo(-1, 0, 2), hi(3, 1, 2.5f);
    const TriangleMesh b = make_box(lo, hi);
    EXPECT_EQ(b.vertex_count(), 24u);
    EXPECT_EQ(b.triangle_count(), 12u);
    EXPECT_NO_THROW(validate(b));
    EXPECT_EQ(b.bounds().lo, lo);
    EXPECT_EQ(b.bounds().hi, hi);
    EXPECT_NEAR(total_area(b), BBox(lo, hi).surface_area(), 1e-5);
    EXPECT_NEAR(signed_volume(b), 4.0 * 1.0 * 0.5, 1e-5);
    const glm::vec3 center = 0.5f * (lo + hi);
    for (std::size_t i = 0; i < b.triangle_count(); ++i) {
        const Triangle t = b.triangle(i);
        const glm::vec3 n = b.normals[b.triangles[i].x];
        EXPECT_GT(glm::dot(area_normal(t), n), 0.0f) << "triangle " << i;
        EXPECT_GT(glm::dot(n, centroid(t) - center), 0.0f) << "triangle " << i;
    }
    EXPECT_THROW((void)make_box(hi, lo), Error);
}

TEST(Procedural, BadParametersNameTheParameter) {
    EXPECT_NE(error_of([] { (void)make_uv_sphere({}, 1, 2, 4); }).find("segments = 2"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)make_uv_sphere({}, 1, 8, 1); }).find("rings = 1"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)make_uv_sphere({}, -1, 8, 4); }).find("radius"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)make_icosphere({}, 1, 11); }).find("subdivisions = 11"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)make_teapot(0); }).find("tessellation = 0"), std::string::npos);
}

TEST(Procedural, TeapotCountsFollowTheFormula) {
    for (int n : {1, 2, 3, 7}) {
        const TriangleMesh t = make_teapot(n);
        const auto nn = static_cast<std::size_t>(n);
        EXPECT_EQ(t.triangle_count(), 64 * nn * nn);
        EXPECT_EQ(t.triangle_count(), teapot_triangle_count(n));
        EXPECT_EQ(t.vertex_count(), 32 * (nn + 1) * (nn + 1));
        EXPECT_EQ(t.normals.size(), t.vertex_count());
        EXPECT_EQ(t.uvs.size(), t.vertex_count());
        EXPECT_NO_THROW(validate(t));
    }
}

TEST(Procedural, TeapotNormalsAreUnitOutwardAndMatchTheWinding) {
    const int n = 8;
    const TriangleMesh t = make_teapot(n);
    for (const glm::vec3& nv : t.normals) EXPECT_NEAR(glm::length(nv), 1.0f, 1e-5f);
    std::size_t degenerate = 0;
    for (std::size_t i = 0; i < t.triangle_count(); ++i) {
        const glm::vec3 an = area_normal(t.triangle(i));
        if (an == glm::vec3(0.0f)) {
            ++degenerate;
            continue;
        }
        const glm::uvec3 c = t.triangles[i];
        EXPECT_GT(glm::dot(an, t.normals[c.x] + t.normals[c.y] + t.normals[c.z]), 0.0f) << i;
    }
    EXPECT_EQ(degenerate, 8u * n);  // collapsed edges of the 4 lid-top and 4 bottom patches
    // Outward overall: positive enclosed volume, about 0.79 in these units.
    EXPECT_NEAR(signed_volume(t), 0.785, 0.01);
    // The lid's knob and the bottom's centre (collapsed edges) get the axis as normal.
    const std::size_t per_patch = (n + 1) * (n + 1);
    EXPECT_NEAR(t.normals[20 * per_patch].y, 1.0f, 1e-5f);   // first lid patch, u = 0
    EXPECT_NEAR(t.normals[28 * per_patch].y, -1.0f, 1e-5f);  // first bottom patch, u = 0
}

TEST(Procedural, TeapotExtentsAreAsDocumented) {
    const BBox fine = make_teapot(48).bounds();
    EXPECT_NEAR(fine.lo.x, -1.0f, 1e-4f);
    EXPECT_NEAR(fine.hi.x, 1.0f, 1e-4f);
    EXPECT_NEAR(fine.lo.y, -0.4896f, 1e-4f);
    EXPECT_NEAR(fine.hi.y, 0.4896f, 1e-4f);
    EXPECT_NEAR(fine.lo.z, -0.6217f, 1e-4f);
    EXPECT_NEAR(fine.hi.z, 0.6217f, 1e-4f);
    // A coarse grid lies inside the same box (Bezier surfaces lie in their hull, and every grid
    // point is on the surface).
    const BBox coarse = make_teapot(3).bounds();
    EXPECT_TRUE(BBox(glm::vec3(-1.0f, -0.4896f, -0.6217f) - 1e-4f,
                     glm::vec3(1.0f, 0.4896f, 0.6217f) + 1e-4f)
                    .contains(coarse.lo));
    EXPECT_LE(coarse.hi.x, 1.0f + 1e-4f);
}

TEST(Procedural, TeapotTessellationForTarget) {
    EXPECT_EQ(teapot_tessellation_for(0), 1);
    EXPECT_EQ(teapot_tessellation_for(64), 1);
    EXPECT_EQ(teapot_tessellation_for(65), 2);
    EXPECT_EQ(teapot_tessellation_for(1000), 4);  // 64 * 16 = 1024
    EXPECT_EQ(teapot_tessellation_for(1'000'000), 125);
    EXPECT_EQ(teapot_tessellation_for(1'000'001), 126);
    EXPECT_THROW((void)teapot_tessellation_for(std::size_t{1} << 40), Error);
    const TriangleMesh small = make_teapot_with_triangles(1000);
    EXPECT_GE(small.triangle_count(), 1000u);
    EXPECT_EQ(small.triangle_count(), 1024u);
}

// A million triangles at the tessellation teapot_tessellation_for picks: the counts
// follow from it in closed form (32 patches of 126 x 126 vertices). How long it takes is
// not asserted: that depends on the machine and its load.
TEST(Procedural, MillionTriangleTeapot) {
    const TriangleMesh big = make_teapot_with_triangles(1'000'000);
    EXPECT_GE(big.triangle_count(), 1'000'000u);
    EXPECT_EQ(big.vertex_count(), 32u * 126u * 126u);
}
