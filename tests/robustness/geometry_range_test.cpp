// Issue 10, defect 6: geometry that silently vanished or was refused for the wrong reason.
// Centres of boxes and triangles near +-3e38 overflowed; triangles beyond the range where
// the watertight test's distance fits a float were never hit; a polygon with a zero-width
// spike was ear-clipped into overlapping triangles.

#include "robustness/robustness_util.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/obj/obj.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;

namespace {

/// Total area of a mesh's triangles.
double total_area(const TriangleMesh& m) {
    double area = 0.0;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        area += 0.5 * double(glm::length(area_normal(m.triangle(i))));
    }
    return area;
}

/// A triangle of half-width w in the plane z = 0, around the origin.
TriangleMesh wide_triangle(float w) {
    TriangleMesh m;
    m.positions = {{-w, -w, 0.0f}, {w, -w, 0.0f}, {0.0f, w, 0.0f}};
    m.triangles = {{0, 1, 2}};
    return m;
}

}  // namespace

TEST(GeometryRange, CentresNearTheFloatLimitAreFinite) {
    const float big = 3e38f;
    const Triangle t{{big, big, big}, {big, 0.9f * big, big}, {0.9f * big, big, -big}};
    const glm::vec3 c = centroid(t);
    EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
    EXPECT_NEAR(c.x / big, (2.9f / 3.0f), 1e-6f);
    const BBox box = bounds(t);
    const glm::vec3 bc = box.center();
    EXPECT_TRUE(std::isfinite(bc.x) && std::isfinite(bc.y) && std::isfinite(bc.z));
    EXPECT_EQ(bc.x, 0.5f * box.lo.x + 0.5f * box.hi.x);
    // A BVH over such boxes builds (it was refused as "non-finite centre").
    const std::vector<BBox> boxes = {box,
                                     bounds(Triangle{{-big, 0, 0}, {-big, 1, 0}, {-big, 0, 1}})};
    const std::vector<glm::vec3> centres = {box.center(), boxes[1].center()};
    EXPECT_EQ(build_sah_bvh(boxes, centres).prim_indices.size(), 2u);
    EXPECT_EQ(build_median_bvh(boxes, centres).prim_indices.size(), 2u);
}

TEST(GeometryRange, TrianglesAtTheRangeLimitAreHitFromNearAndFar) {
    // Half-width 2^40 = kMaxMeshCoordinate: every ray towards the triangle hits it, from
    // distance 55 as from a corner of the range.
    const TriangleMesh m = wide_triangle(kMaxMeshCoordinate);
    validate(m);
    const TriangleBvh bvh(m);
    const TriangleList list(m);
    std::mt19937 rng(11);
    // Targets in [-0.25, 0.25] x [-0.5, 0] times the half-width: inside the triangle.
    std::uniform_real_distribution<float> u(-0.25f, 0.25f), v(-0.5f, 0.0f);
    const float far = kMaxMeshCoordinate;
    for (const glm::vec3 origin :
         {glm::vec3(0, 0, 55), glm::vec3(far, far, far), glm::vec3(-far, 0.5f * far, -55.0f)}) {
        for (int i = 0; i < 100; ++i) {
            const glm::vec3 target{u(rng) * kMaxMeshCoordinate, v(rng) * kMaxMeshCoordinate, 0};
            Ray ray;
            ray.origin = origin;
            ray.direction = glm::normalize(target - origin);
            EXPECT_TRUE(list.intersect(ray).valid()) << "ray " << i << " from z " << origin.z;
            EXPECT_TRUE(bvh.intersect(ray).valid()) << "ray " << i << " from z " << origin.z;
        }
    }
}

TEST(GeometryRange, MeshesBeyondTheRangeAreRefusedNotSilentlyMissed) {
    // The case: 2e18 wide, seen from 55 away, was never hit; now refused.
    const TriangleMesh m = wide_triangle(1e18f);
    const std::string msg = error_of([&] { validate(m); });
    EXPECT_TRUE(has(msg,
                    "mesh: position 0 = (-1e+18, -1e+18, 0) is outside the representable "
                    "range |coordinate| <= 2^40"))
        << msg;
    ScratchDir dir;
    const auto path = dir.write("huge.obj", "v -1e18 0 0\nv 1e18 0 0\nv 0 1e18 0\nf 1 2 3\n");
    std::vector<std::string> w;
    ObjLoadOptions options;
    options.warnings = &w;
    const std::string load_msg = error_of([&] { (void)load_obj(path, options); });
    EXPECT_TRUE(has(load_msg, path.string() + ": mesh: position 0")) << load_msg;
    EXPECT_TRUE(has(load_msg, "representable range")) << load_msg;
}

TEST(GeometryRange, ZeroWidthSpikeKeepsThePolygonsArea) {
    ScratchDir dir;
    std::vector<std::string> w;
    ObjLoadOptions options;
    options.warnings = &w;
    // A 2 x 2 square with a spike from (2, 1) out to (4, 1) and back: area 4.
    const TriangleMesh m = load_obj(dir.write("spike.obj",
                                              "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 4 1 0\n"
                                              "v 2 2 0\nv 0 2 0\nf 1 2 3 4 3 5 6\n"),
                                    options);
    EXPECT_NEAR(total_area(m), 4.0, 1e-6);
    EXPECT_TRUE(w.empty()) << w.front();
    // The same with the spike's base as a separate vertex at the same place.
    const TriangleMesh m2 = load_obj(dir.write("spike2.obj",
                                               "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 4 1 0\nv 2 1 0\n"
                                               "v 2 2 0\nv 0 2 0\nf 1 2 3 4 5 6 7\n"),
                                     options);
    EXPECT_NEAR(total_area(m2), 4.0, 1e-6);
    // A keyhole (a square with a square hole joined by a zero-width bridge): area 16 - 4.
    const TriangleMesh key = load_obj(dir.write("keyhole.obj",
                                                "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\n"
                                                "v 1 1 0\nv 1 3 0\nv 3 3 0\nv 3 1 0\n"
                                                "f 1 2 3 4 1 5 6 7 8 5\n"),
                                      options);
    EXPECT_NEAR(total_area(key), 12.0, 1e-6);
    EXPECT_TRUE(w.empty()) << w.front();
    // A lopsided bow tie (edges 2-3 and 4-1 cross) overlaps itself: no triangulation has
    // its signed area; refused with a warning.
    const TriangleMesh bow = load_obj(
        dir.write("bow.obj", "v 0 0 0\nv 4 0 0\nv 0 2 0\nv 1 2 0\nf 1 2 3 4\nf 1 2 3\n"), options);
    EXPECT_EQ(bow.triangle_count(), 1u);
    ASSERT_EQ(w.size(), 1u);
    EXPECT_TRUE(has(w[0], "bow.obj: 1 polygon(s) overlapping themselves (first: face 1)")) << w[0];
}
