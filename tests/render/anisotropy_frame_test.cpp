// The anisotropy direction Scene::shade gives an anisotropic material at a hit: on a
// sphere the tangent is dP/du (toward increasing u of sphere_uv), on a mesh with uvs its
// generated tangent (toward increasing u), turned by anisotropy_rotation counter-clockwise
// toward the bitangent (increasing v); anisotropyTexture's RG turns it further and its B
// scales the strength; a mesh without uvs leaves the direction to the BSDF's frame.

#include <librt/core/error.h>
#include <librt/geometry/sphere.h>
#include <librt/material/material.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

namespace librt {
namespace {

constexpr float kHalfPi = 0.5f * std::numbers::pi_v<float>;

Material brushed(float rotation) {
    Material m = Material::conductor(Metal::Aluminium, 0.3f);
    m.anisotropy = 0.8f;
    m.anisotropy_rotation = rotation;
    return m;
}

// The square [-1, 1]^2 at z = 0 facing +z, uvs (v up) from (0, 0) at (-1, -1) to (1, 1).
TriangleMesh quad(bool with_uvs) {
    TriangleMesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    if (with_uvs) m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

/// The shaded material at the hit of `ray`, and the hit.
struct Shaded {
    Hit hit;
    Material material;
};
Shaded shade_at(const Scene& scene, const Ray& ray) {
    Shaded s;
    EXPECT_TRUE(scene.intersect_for_shading(ray, s.hit));
    ShadedMaterial scratch;
    s.material = scene.shade(s.hit, ray.direction, scratch);
    return s;
}

void expect_near(const glm::vec3& got, const glm::vec3& want, const char* what) {
    EXPECT_NEAR(got.x, want.x, 1e-5f) << what;
    EXPECT_NEAR(got.y, want.y, 1e-5f) << what;
    EXPECT_NEAR(got.z, want.z, 1e-5f) << what;
}

TEST(AnisotropyFrame, SphereTangentIsDpDuTurnedTowardTheBitangent) {
    for (const float rotation : {0.0f, 0.5f, kHalfPi}) {
        Scene scene;
        const Sphere sphere{{0, 0, 0}, 1.0f};
        scene.add_sphere(sphere, scene.add_material(brushed(rotation)));
        scene.commit();
        for (const glm::vec3 dir :
             {glm::vec3(-1, -0.2f, 0.1f), glm::vec3(0.3f, -1, 0.4f), glm::vec3(0.5f, 0.2f, -1)}) {
            const Ray ray(-3.0f * dir, glm::normalize(dir));
            const Shaded s = shade_at(scene, ray);
            const glm::vec3 n = s.hit.geometric_normal;
            const glm::vec3 d = s.material.anisotropy_direction;
            EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(d, n), 0.0f, 1e-5f);
            // The unturned tangent t points toward increasing u (checked by a finite step
            // on sphere_uv), and b = n x t; d = cos r t + sin r b.
            const glm::vec3 t = glm::normalize(glm::vec3(-n.z, 0.0f, n.x));
            const float u0 = sphere_uv(sphere, n).x;
            const float u1 = sphere_uv(sphere, glm::normalize(n + 1e-3f * t)).x;
            EXPECT_GT(u1, u0);
            expect_near(d, std::cos(rotation) * t + std::sin(rotation) * glm::cross(n, t),
                        "sphere");
        }
    }
}

TEST(AnisotropyFrame, MeshTangentFollowsTheUvsAndTheRotationTurnsTowardIncreasingV) {
    for (const auto& [rotation, want] :
         {std::pair{0.0f, glm::vec3(1, 0, 0)}, std::pair{kHalfPi, glm::vec3(0, 1, 0)},
          std::pair{-0.5f, glm::vec3(std::cos(0.5f), -std::sin(0.5f), 0)}}) {
        Scene scene;
        scene.add_mesh(quad(true), scene.add_material(brushed(rotation)));
        scene.commit();
        const Shaded s = shade_at(scene, Ray({0.2f, 0.3f, 2}, {0, 0, -1}));
        expect_near(s.material.anisotropy_direction, want, "quad");
        EXPECT_FLOAT_EQ(s.material.anisotropy, 0.8f);
    }
    // Seen from below, the same surface direction (the frame is the surface's, not the ray's).
    Scene scene;
    scene.add_mesh(quad(true), scene.add_material(brushed(kHalfPi)));
    scene.commit();
    expect_near(shade_at(scene, Ray({0.2f, 0.3f, -2}, {0, 0, 1})).material.anisotropy_direction,
                {0, 1, 0}, "quad from below");
}

TEST(AnisotropyFrame, TextureTurnsTheDirectionAndScalesTheStrength) {
    Scene scene;
    Material m = brushed(0.25f);
    // Direction at 0.5 rad in tangent space, strength 0.5 (linear texels, no filtering).
    const float a = 0.5f;
    ImageTexture tex(1, 1, {{0.5f + 0.5f * std::cos(a), 0.5f + 0.5f * std::sin(a), 0.5f}});
    tex.set_sampling({TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
    m.anisotropy_texture.texture = scene.add_texture(std::move(tex));
    scene.add_mesh(quad(true), scene.add_material(m));
    scene.commit();
    const Shaded s = shade_at(scene, Ray({-0.4f, 0.1f, 2}, {0, 0, -1}));
    expect_near(s.material.anisotropy_direction, {std::cos(0.75f), std::sin(0.75f), 0}, "texture");
    EXPECT_NEAR(s.material.anisotropy, 0.4f, 1e-6f);
}

// An instance of a prototype added without tangents: the anisotropic material placed on it
// gets tangents from the prototype's uvs, mapped by the instance (a quarter turn about z
// takes the u direction +x to +y), as a mesh added whole gets them.
TEST(AnisotropyFrame, InstanceOfAPrototypeWithoutTangentsGetsThemFromItsUvs) {
    Scene scene;
    const std::uint32_t prototype = scene.add_mesh_prototype(quad(true));
    const glm::mat4 quarter_turn(glm::vec4(0, 1, 0, 0), glm::vec4(-1, 0, 0, 0),
                                 glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1));
    scene.add_instance(prototype, quarter_turn, scene.add_material(brushed(0.0f)));
    scene.commit();
    const Shaded s = shade_at(scene, Ray({0.2f, 0.3f, 2}, {0, 0, -1}));
    expect_near(s.material.anisotropy_direction, {0, 1, 0}, "instance");
    EXPECT_FLOAT_EQ(s.material.anisotropy, 0.8f);
}

TEST(AnisotropyFrame, MeshWithoutUvsLeavesTheDirectionToTheBsdfFrame) {
    Scene scene;
    scene.add_mesh(quad(false), scene.add_material(brushed(0.3f)));
    scene.commit();
    const Shaded s = shade_at(scene, Ray({0.2f, 0.3f, 2}, {0, 0, -1}));
    EXPECT_EQ(s.material.anisotropy_direction, glm::vec3(0.0f));
    EXPECT_FLOAT_EQ(s.material.anisotropy, 0.8f);
}

TEST(AnisotropyFrame, BadAnisotropyIsRejectedNamingTheParameter) {
    Material m = brushed(0.0f);
    m.anisotropy = 1.5f;
    try {
        validate(m);
        ADD_FAILURE() << "anisotropy 1.5 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("anisotropy = 1.5"), std::string::npos) << e.what();
    }
    m = brushed(std::nanf(""));
    EXPECT_THROW(validate(m), Error);
    m = brushed(0.0f);
    m.anisotropy_direction.x = std::numeric_limits<float>::infinity();
    EXPECT_THROW(validate(m), Error);
    m = brushed(0.0f);
    m.anisotropy_texture.texture = -2;
    EXPECT_THROW(validate(m), Error);
}

}  // namespace
}  // namespace librt
