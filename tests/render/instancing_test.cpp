// Instances against baked copies: a prototype placed by K transforms must give the hits
// of the same K meshes baked by transform() (tolerances derived from float rounding).

#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace librt {
namespace {

constexpr float kEps = 0x1p-24f;  // float unit roundoff

enum class Placement { Rotation, NonUniform, Mirror, MirrorNonUniform };

struct InstancingCase {
    Placement placement;
    int instances;  // 8 keeps the flat top level, 24 takes the top-level BVH
    const char* name;
};

/// Spectral-norm bound (Frobenius norm) of a matrix's linear part.
float frobenius(const glm::mat3& m) {
    return std::sqrt(glm::dot(m[0], m[0]) + glm::dot(m[1], m[1]) + glm::dot(m[2], m[2]));
}

/// K placements of the kind asked, on a grid spaced so no two instances overlap.
std::vector<glm::mat4> make_placements(Placement kind, int count, float radius, std::mt19937& rng) {
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    std::vector<glm::mat4> out;
    const float spacing = 2.0f * radius * 2.0f * 1.1f;  // diameter at the largest scale (2)
    for (int k = 0; k < count; ++k) {
        glm::vec3 axis(U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f);
        axis = glm::normalize(axis + glm::vec3(1e-3f));
        const float angle = glm::two_pi<float>() * U(rng);
        glm::vec3 scale(1.0f);
        if (kind == Placement::NonUniform || kind == Placement::MirrorNonUniform)
            scale = glm::vec3(0.5f + 1.5f * U(rng), 0.5f + 1.5f * U(rng), 0.5f + 1.5f * U(rng));
        if (kind == Placement::Mirror || kind == Placement::MirrorNonUniform)
            scale[k % 3] = -scale[k % 3];  // determinant < 0
        const glm::vec3 cell(float(k % 4), float((k / 4) % 3), float(k / 12));
        glm::mat4 m =
            glm::translate(glm::mat4(1.0f), spacing * cell + glm::vec3(3.0f, -7.0f, 5.0f));
        m = glm::rotate(m, angle, axis);
        m = glm::scale(m, scale);
        out.push_back(m);
    }
    return out;
}

/// Distance from p to the nearest edge of triangle (a, b, c).
float edge_distance(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                    const glm::vec3& c) {
    const auto segment = [&](const glm::vec3& u, const glm::vec3& v) {
        const glm::vec3 e = v - u;
        const float s =
            glm::clamp(glm::dot(p - u, e) / std::max(glm::dot(e, e), 1e-30f), 0.0f, 1.0f);
        return glm::length(p - (u + s * e));
    };
    return std::min(std::min(segment(a, b), segment(b, c)), segment(c, a));
}

class Instancing : public ::testing::TestWithParam<InstancingCase> {};

TEST_P(Instancing, SameHitsAsBakedCopies) {
    const InstancingCase param = GetParam();
    std::mt19937 rng(1234u + std::uint32_t(param.placement) * 17u + std::uint32_t(param.instances));
    // A non-convex closed-ish mesh with vertex normals: rays meet several layers.
    const TriangleMesh prototype = make_teapot(8);
    const BBox proto_box = prototype.bounds();
    const float radius = 0.5f * glm::length(proto_box.diagonal()) + glm::length(proto_box.center());
    const std::vector<glm::mat4> placements =
        make_placements(param.placement, param.instances, radius, rng);

    Scene baked, instanced;
    const auto mb = baked.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto mi = instanced.add_material(Material::diffuse(glm::vec3(0.5f)));
    const std::uint32_t proto_id = instanced.add_mesh_prototype(prototype);
    std::vector<BBox> world_boxes;
    for (const glm::mat4& m : placements) {
        TriangleMesh copy = prototype;
        transform(copy, m);
        world_boxes.push_back(copy.bounds());
        EXPECT_EQ(baked.add_mesh(std::move(copy), mb), world_boxes.size() - 1);
        EXPECT_EQ(instanced.add_instance(proto_id, m, mi), world_boxes.size() - 1);
    }
    baked.commit();
    instanced.commit();
    ASSERT_EQ(instanced.instance_count(), placements.size());

    // Rays from a sphere around everything toward a random point of a random instance's box.
    BBox all = baked.bounds();
    const glm::vec3 center = all.center();
    const float world_radius = 0.75f * glm::length(all.diagonal());
    // Largest coordinate any ray or hit involves: what float rounding is relative to.
    const float scale = glm::length(center) + world_radius;
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    std::uniform_int_distribution<int> pick(0, param.instances - 1);

    constexpr int kRays = 100'000;
    int hits = 0, edge_cases = 0, any_hit_checked = 0;
    for (int i = 0; i < kRays; ++i) {
        const float z = 1.0f - 2.0f * U(rng);
        const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const float phi = glm::two_pi<float>() * U(rng);
        Ray ray;
        ray.origin = center + world_radius * glm::vec3(s * std::cos(phi), s * std::sin(phi), z);
        const BBox& target_box = world_boxes[std::size_t(pick(rng))];
        const glm::vec3 target =
            target_box.lo + target_box.diagonal() * glm::vec3(U(rng), U(rng), U(rng));
        // Not unit length on purpose: t must carry over whatever the direction's length.
        ray.direction = (target - ray.origin) * (0.25f + U(rng));

        Hit hb, hi;
        const bool found_b = baked.intersect(ray, hb);
        const bool found_i = instanced.intersect(ray, hi);
        const float dlen = glm::length(ray.direction);

        // Position tolerance of a hit: the object-space ray and the mapped-back point each
        // carry a few roundings relative to the largest coordinate, amplified by the
        // instance's condition number |M| |M^-1|; 32 ulps of that bounds them generously.
        const auto position_tolerance = [&](std::uint32_t k) {
            const glm::mat3 m(placements[k]);
            return 32.0f * kEps * frobenius(m) * frobenius(glm::inverse(m)) * scale;
        };
        if (found_b != found_i) {
            // Only a ray grazing a silhouette edge may disagree: the hit that exists lies
            // within rounding of its triangle's edge.
            const Hit& h = found_b ? hb : hi;
            const std::uint32_t k = found_b ? hb.object_id : hi.instance_id;
            const Triangle tri = prototype.triangle(h.primitive_id);
            const glm::mat4& m = placements[k];
            const auto w = [&](const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); };
            EXPECT_LE(edge_distance(h.point, w(tri.p0), w(tri.p1), w(tri.p2)),
                      position_tolerance(k))
                << "ray " << i << ": hit in one scene only, away from any edge";
            ++edge_cases;
            continue;
        }
        const bool occluded_b = baked.occluded(ray), occluded_i = instanced.occluded(ray);
        EXPECT_EQ(occluded_b, found_b) << "ray " << i;
        EXPECT_EQ(occluded_i, found_i) << "ray " << i;
        if (!found_b) continue;
        ++hits;

        const std::uint32_t k = hb.object_id;  // baked mesh k is instance k
        ASSERT_LT(k, placements.size());
        EXPECT_EQ(hb.instance_id, kInvalidId);
        EXPECT_EQ(hi.instance_id, k) << "ray " << i;
        EXPECT_EQ(hi.object_id, instanced.instance_object(k)) << "ray " << i;
        const float tol_p = position_tolerance(k);
        // A ray displaced by tol_p meets the surface up to tol_p / cos theta away, which
        // moves t by that / |d|.
        const float cos_theta =
            std::max(std::fabs(glm::dot(ray.direction, hb.geometric_normal)) / dlen, 1e-3f);
        EXPECT_LE(glm::length(hi.point - hb.point), tol_p / cos_theta) << "ray " << i;
        const float tol_t = tol_p / (dlen * cos_theta);
        EXPECT_NEAR(hi.t, hb.t, tol_t) << "ray " << i;

        if (hi.primitive_id != hb.primitive_id) {
            // Neighbouring triangles of one shared edge: the same point, on that edge.
            const Triangle tri = prototype.triangle(hb.primitive_id);
            const glm::mat4& m = placements[k];
            const auto w = [&](const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); };
            EXPECT_LE(edge_distance(hb.point, w(tri.p0), w(tri.p1), w(tri.p2)), tol_p)
                << "ray " << i << ": different triangle away from any edge";
            ++edge_cases;
        } else {
            // The baked normal is the cross of edges of corners rounded in world space
            // (each off by ~eps * scale), the instance's the cross of object-space edges
            // mapped by the inverse transpose: the unit cross of edges e1, e2 with errors
            // ~d moves by about d (|e1| + |e2|) / |e1 x e2|. Interpolated normals add the
            // barycentrics' error (a point error tol_p over the triangle's height) times
            // the spread of the vertex normals, and the normal matrices' rounding.
            const Triangle tri = prototype.triangle(hb.primitive_id);
            const glm::mat4& mk = placements[k];
            const auto w = [&](const glm::vec3& p) { return glm::vec3(mk * glm::vec4(p, 1.0f)); };
            const glm::vec3 e1 = w(tri.p1) - w(tri.p0), e2 = w(tri.p2) - w(tri.p0);
            const float spread = (glm::length(e1) + glm::length(e2) + glm::length(e2 - e1)) /
                                 std::max(glm::length(glm::cross(e1, e2)), 1e-30f);
            const glm::mat3 m(mk);
            const float kappa = frobenius(m) * frobenius(glm::inverse(m));
            const float tol_ng = 8.0f * kEps * (scale * spread + kappa * kappa);
            const glm::uvec3 idx = prototype.triangles[hb.primitive_id];
            const glm::vec3 n0 = prototype.normals[idx.x], n1 = prototype.normals[idx.y],
                            n2 = prototype.normals[idx.z];
            const float normal_range =
                glm::length(n1 - n0) + glm::length(n2 - n1) + glm::length(n0 - n2);
            const float tol_ns = tol_ng + kappa * tol_p * spread * normal_range;
            EXPECT_LE(glm::length(hi.geometric_normal - hb.geometric_normal), tol_ng)
                << "ray " << i;
            EXPECT_LE(glm::length(hi.shading_normal - hb.shading_normal), tol_ns) << "ray " << i;
            EXPECT_GT(glm::dot(hi.geometric_normal, hb.geometric_normal), 0.0f);
        }

        // Any-hit with the segment cut short of the hit, and just past it.
        if (hb.t > 4.0f * tol_t) {
            Ray shorter = ray, longer = ray;
            shorter.t_max = hb.t - 2.0f * tol_t;
            longer.t_max = hb.t + 2.0f * tol_t;
            EXPECT_FALSE(baked.occluded(shorter)) << "ray " << i;
            EXPECT_FALSE(instanced.occluded(shorter)) << "ray " << i;
            EXPECT_TRUE(baked.occluded(longer)) << "ray " << i;
            EXPECT_TRUE(instanced.occluded(longer)) << "ray " << i;
            // Ignoring the object hit: both scenes see the same thing behind it.
            EXPECT_EQ(baked.occluded(ray, hb.object_id), instanced.occluded(ray, hi.object_id))
                << "ray " << i;
            ++any_hit_checked;
        }
    }
    // The rays aim at the instances: most must hit, or the comparison proves little.
    EXPECT_GT(hits, kRays / 4);
    EXPECT_GT(any_hit_checked, kRays / 4);
    std::cout << param.name << ": " << hits << " hits of " << kRays << " rays, " << edge_cases
              << " on an edge\n";
}

INSTANTIATE_TEST_SUITE_P(Placements, Instancing,
                         ::testing::Values(InstancingCase{Placement::Rotation, 8, "rotation"},
                                           InstancingCase{Placement::NonUniform, 24, "non_uniform"},
                                           InstancingCase{Placement::Mirror, 8, "mirror"},
                                           InstancingCase{Placement::MirrorNonUniform, 24,
                                                          "mirror_non_uniform"}),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

// Mirroring, checked without transform(): a sphere's normals must still point outward.
TEST(Instancing, MirroredNormalsPointOutward) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const std::uint32_t proto = scene.add_mesh_prototype(make_uv_sphere({0, 0, 0}, 1.0f, 48, 24));
    const glm::vec3 centre(2.0f, -1.0f, 0.5f);
    const glm::mat4 mirror =
        glm::scale(glm::translate(glm::mat4(1.0f), centre), glm::vec3(-1.5f, 0.75f, 1.0f));
    ASSERT_LT(glm::determinant(glm::mat3(mirror)), 0.0f);
    scene.add_instance(proto, mirror, m);
    scene.commit();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(-1.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 dir = glm::normalize(glm::vec3(U(rng), U(rng), U(rng)) + glm::vec3(1e-3f));
        Ray ray{centre + 5.0f * dir, -dir + 0.2f * glm::vec3(U(rng), U(rng), U(rng))};
        Hit hit;
        if (!scene.intersect(ray, hit)) continue;
        ++hits;
        // The ellipsoid's outward normal at p is the gradient of its implicit function:
        // (p - c) / s^2 componentwise.
        const glm::vec3 q = hit.point - centre;
        const glm::vec3 outward = glm::normalize(q / glm::vec3(2.25f, 0.5625f, 1.0f));
        EXPECT_GT(glm::dot(hit.geometric_normal, outward), 0.9f) << "ray " << i;
        EXPECT_GT(glm::dot(hit.shading_normal, outward), 0.9f) << "ray " << i;
        EXPECT_LT(glm::dot(hit.geometric_normal, ray.direction), 0.0f) << "ray " << i;
        EXPECT_EQ(hit.instance_id, 0u);
    }
    EXPECT_GT(hits, 1000);
}

TEST(Instancing, RejectsBadInput) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const std::uint32_t proto = scene.add_mesh_prototype(make_box({0, 0, 0}, {1, 1, 1}));
    EXPECT_THROW(scene.add_instance(proto + 1, glm::mat4(1.0f), m), Error);
    EXPECT_THROW(scene.add_instance(proto, glm::mat4(1.0f), m + 1), Error);
    glm::mat4 bad(1.0f);
    bad[1][2] = std::nanf("");
    EXPECT_THROW(scene.add_instance(proto, bad, m), Error);
    glm::mat4 projective(1.0f);
    projective[0][3] = 0.5f;
    EXPECT_THROW(scene.add_instance(proto, projective, m), Error);
    EXPECT_THROW(scene.add_instance(proto, glm::scale(glm::mat4(1.0f), {1, 0, 1}), m), Error);
    EXPECT_EQ(scene.object_count(), 0u);
    EXPECT_EQ(scene.instance_count(), 0u);
    // A prototype alone is not geometry.
    scene.commit();
    Hit hit;
    EXPECT_FALSE(scene.intersect(Ray{{0.5f, 0.5f, 5.0f}, {0, 0, -1}}, hit));
}

}  // namespace
}  // namespace librt
