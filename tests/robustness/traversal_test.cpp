// Traversal safety: the builders bound the tree depth by kMaxBvhDepth (so the fixed-size
// traversal stack cannot overflow) even on input built to make the report's median split
// as deep as possible; rays that cannot hit anything (NaN, zero or infinite direction,
// NaN or inverted range) terminate and miss; degenerate triangles are never hit.

#include "robustness/robustness_util.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;

namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// Triangle k spans x in [a, 1.5a] (and a/2 in y, a/4 in z) with a = 2^-k. The median
/// split cuts the node box at the middle of its longest side (x), which separates exactly
/// one triangle per level: without a cap the tree would be `count` levels deep.
std::vector<Triangle> exponential_triangles(int count) {
    std::vector<Triangle> tris;
    for (int k = 0; k < count; ++k) {
        const float a = std::ldexp(1.0f, -k);
        tris.push_back({{a, -0.25f * a, 0.0f},
                        {1.5f * a, -0.25f * a, 0.0f},
                        {1.25f * a, 0.25f * a, 0.25f * a}});
    }
    return tris;
}

/// The real depth of a tree, walked from the root (not trusting Bvh::depth).
std::uint32_t walked_depth(const Bvh& bvh, std::uint32_t node = 0, std::uint32_t depth = 0) {
    const BvhNode& n = bvh.nodes[node];
    if (n.is_leaf()) return depth;
    return std::max(walked_depth(bvh, n.index, depth + 1),
                    walked_depth(bvh, n.index + 1, depth + 1));
}

/// The rays that must terminate and miss, whatever the scene.
std::vector<Ray> untraceable_rays() {
    std::vector<Ray> rays;
    const auto add = [&](glm::vec3 o, glm::vec3 d, float t_min = 0.0f, float t_max = kInf) {
        Ray r;
        r.origin = o;
        r.direction = d;
        r.t_min = t_min;
        r.t_max = t_max;
        rays.push_back(r);
    };
    const glm::vec3 o{0.2f, 0.2f, 5.0f}, d{0.0f, 0.0f, -1.0f};
    add(o, {0, 0, 0});             // zero direction
    add(o, {1e-30f, 0, -1e-30f});  // so small its squared length underflows to 0
    add(o, {kNan, 0, -1});         // NaN direction
    add(o, {0, 0, -kInf});         // infinite direction
    add(o, {kInf, kInf, -kInf});
    add({kNan, 0.2f, 5}, d);   // NaN origin
    add({0.2f, -kInf, 5}, d);  // infinite origin
    add(o, d, kNan);           // NaN t_min
    add(o, d, 0.0f, kNan);     // NaN t_max
    add(o, d, 10.0f, 1.0f);    // empty range
    return rays;
}

}  // namespace

TEST(Traversal, MedianBuilderDepthIsCappedOnExponentialInput) {
    const std::vector<Triangle> tris = exponential_triangles(110);
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centers;
    for (const Triangle& t : tris) {
        boxes.push_back(bounds(t));
        centers.push_back(boxes.back().center());
    }
    for (const BvhBuilder builder : {BvhBuilder::Median, BvhBuilder::Sah}) {
        const Bvh bvh = build_bvh(builder, boxes, centers);
        EXPECT_LE(bvh.depth, kMaxBvhDepth);
        EXPECT_EQ(walked_depth(bvh), bvh.depth);  // the field tells the truth
        std::size_t slots = 0;
        for (const BvhNode& n : bvh.nodes) slots += n.prim_count;
        EXPECT_EQ(slots, tris.size());
        if (builder == BvhBuilder::Median) {
            // The input really is pathological: the cap was reached, so the deepest leaf
            // holds the ~45 smallest triangles that could not be separated further.
            EXPECT_EQ(bvh.depth, kMaxBvhDepth);
        }
    }
}

TEST(Traversal, DeepTreeQueriesAgreeWithLinearScan) {
    const std::vector<Triangle> tris = exponential_triangles(110);
    const TriangleList linear(tris);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    for (const BvhBuilder builder : {BvhBuilder::Median, BvhBuilder::Sah}) {
        const TriangleBvh bvh(tris, builder);
        int near_rays = 0, near_hits = 0;
        for (std::size_t k = 0; k < tris.size(); ++k) {
            // Rays at points of each triangle: half from nearby, at the triangle's own
            // scale (they hit it), half from (0.7, 0.1, 2), crossing the boxes of the
            // larger triangles on the way (float rounding decides what those hit).
            const Triangle& t = tris[k];
            const float scale = t.p0.x;
            for (int i = 0; i < 20; ++i) {
                const float u = U(rng), v = U(rng) * (1.0f - u);
                const glm::vec3 target = t.p0 + u * (t.p1 - t.p0) + v * (t.p2 - t.p0);
                Ray r;
                r.origin = i % 2 == 0
                               ? target + scale * glm::vec3(U(rng) - 0.5f, U(rng) - 0.5f, 1.0f)
                               : glm::vec3(0.7f, 0.1f, 2.0f);
                // Unit length: a direction of length ~2^-100 would have a squared length
                // that underflows, which makes a ray untraceable (it misses everything).
                r.direction = glm::normalize(target - r.origin);
                const PrimitiveHit a = bvh.intersect(r);
                const PrimitiveHit b = linear.intersect(r);
                ASSERT_EQ(a.valid(), b.valid()) << "triangle " << k << " ray " << i;
                ASSERT_EQ(bvh.occluded(r), linear.occluded(r));
                if (a.valid()) {
                    EXPECT_EQ(a.primitive_id, b.primitive_id);
                    EXPECT_EQ(a.t, b.t);
                }
                // Below ~2^-45 the watertight test's distance (a product of three
                // coordinates relative to the origin) underflows float and it misses: a
                // precision limit both walks share, not a traversal question.
                if (i % 2 == 0 && k < 40) {
                    ++near_rays;
                    near_hits += a.valid();
                }
            }
        }
        EXPECT_GE(near_hits, near_rays * 95 / 100) << near_hits << " of " << near_rays;
    }
}

TEST(Traversal, HandMadeTreeDeeperThanTheStackIsRefused) {
    Bvh bvh;
    bvh.nodes.push_back({BBox{{0, 0, 0}, {1, 1, 1}}, 0, 1});
    bvh.prim_indices = {0};
    bvh.depth = kMaxBvhDepth + 1;
    Ray r;
    r.origin = {0.5f, 0.5f, 5.0f};
    const std::string msg =
        error_of([&] { (void)traverse<false>(bvh, r, [](std::uint32_t, Ray&) { return true; }); });
    EXPECT_TRUE(has(msg, "BVH depth 65 exceeds kMaxBvhDepth = 64")) << msg;
}

TEST(Traversal, UntraceableRaysMissInTriangleBvhAndScene) {
    TriangleMesh quad;
    quad.positions = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    const TriangleBvh bvh(quad);
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    (void)scene.add_mesh(quad, grey);
    (void)scene.add_sphere({{0, 0, 0}, 3.0f}, grey);  // contains the rays' origins' targets
    (void)scene.add_sphere({{0.2f, 0.2f, 5.0f}, 1.0f}, grey);  // contains the origins
    scene.commit();
    for (const Ray& ray : untraceable_rays()) {
        EXPECT_FALSE(bvh.intersect(ray).valid());
        EXPECT_FALSE(bvh.occluded(ray));
        Hit hit;
        hit.t = 123.0f;
        EXPECT_FALSE(scene.intersect(ray, hit));
        EXPECT_EQ(hit.t, 123.0f);  // left alone
        EXPECT_FALSE(scene.occluded(ray));
    }
    // The same origin with a sane direction does hit (the misses above are not luck).
    Hit hit;
    EXPECT_TRUE(scene.intersect(Ray{{0.2f, 0.2f, 5.0f}, {0, 0, -1}}, hit));
    EXPECT_TRUE(bvh.intersect(Ray{{0.2f, 0.2f, 5.0f}, {0, 0, -1}}).valid());
}

TEST(Traversal, DegenerateTrianglesAreNeverHit) {
    // Zero area: a point, collinear corners, a repeated corner; each lying across the rays.
    TriangleMesh m;
    m.positions = {{0, 0, 0},  {0, 0, 0}, {0, 0, 0},   // a point
                   {-1, 0, 0}, {0, 0, 0}, {1, 0, 0},   // collinear along x
                   {0, -1, 0}, {0, 1, 0}, {0, -1, 0},  // repeated corner
                   {0, 0, -1}, {0, 0, 0}, {0, 0, 1}};  // collinear along the ray
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}};
    const TriangleBvh bvh(m);
    const TriangleList linear(m);
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    (void)scene.add_mesh(m, grey);
    scene.commit();
    std::vector<Ray> rays;
    for (const glm::vec3 d :
         {glm::vec3(0, 0, -1), glm::vec3(0, -1, 0), glm::vec3(-1, 0, 0), glm::vec3(-1, -1, -1)}) {
        for (const glm::vec3 target : {glm::vec3(0), glm::vec3(0.5f, 0, 0), glm::vec3(0, 0.5f, 0),
                                       glm::vec3(0, 0, 0.5f), glm::vec3(1, 0, 0)}) {
            rays.push_back(Ray{target - 5.0f * d, d});
        }
    }
    for (const Ray& r : rays) {
        EXPECT_FALSE(bvh.intersect(r).valid());
        EXPECT_FALSE(bvh.occluded(r));
        EXPECT_FALSE(linear.intersect(r).valid());
        Hit hit;
        EXPECT_FALSE(scene.intersect(r, hit));
        EXPECT_FALSE(scene.occluded(r));
    }
}

TEST(Traversal, SliverTrianglesGiveFiniteUnitNormals) {
    // Nearly degenerate: areas around 1e-30 and 1e-38, whose cross product underflows.
    // They may be hit; every hit must have a finite t and unit normals.
    TriangleMesh m;
    m.positions = {{-1, -1e-15f, 0},      {1, -1e-15f, 0},      {0, 1e-15f, 0},
                   {-1e-19f, -1e-19f, 1}, {1e-19f, -1e-19f, 1}, {0, 1e-19f, 1}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    m.normals.assign(m.positions.size(), glm::vec3(0.0f));  // zero vertex normals too
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    (void)scene.add_mesh(m, grey);
    scene.commit();
    int hits = 0;
    for (int i = -20; i <= 20; ++i) {
        for (const float z : {0.0f, 1.0f}) {
            const Ray r{{float(i) * 0.05f, 0.0f, z + 3.0f}, {0, 0, -1}};
            Hit hit;
            if (!scene.intersect(r, hit)) continue;
            ++hits;
            EXPECT_TRUE(std::isfinite(hit.t));
            EXPECT_NEAR(glm::length(hit.geometric_normal), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(hit.shading_normal), 1.0f, 1e-5f);
        }
    }
    EXPECT_GT(hits, 0);  // the thin one at z = 0 is hit along its length
}
