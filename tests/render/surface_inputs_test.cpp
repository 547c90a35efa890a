// Per-hit material inputs (Scene::shade): textures times factors, tangent-space normal maps
// with given and generated tangents, one-sided backs, and the alpha test of cut-outs.

#include <librt/geometry/tangents.h>
#include <librt/material/bsdf.h>
#include <librt/material/normal_map.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace librt {
namespace {

// The square [-1, 1]^2 in the plane z = 0, facing +z, uvs (OBJ convention, v up) from
// (0, 0) at (-1, -1) to (1, 1) at (1, 1).
TriangleMesh unit_quad() {
    TriangleMesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

// A 1 x 1 texture of linear value c, read without filtering (so exactly c).
ImageTexture constant(const glm::vec3& c) {
    ImageTexture t(1, 1, {c});
    t.set_sampling({TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
    return t;
}

// The hit of the ray from (x, y, 2) straight down, shaded; returns the shading normal.
glm::vec3 shaded_normal(const Scene& scene, float x, float y, glm::vec3 dir = {0, 0, -1}) {
    Hit hit;
    const Ray ray(glm::vec3(x, y, 0) - 2.0f * dir, dir);
    EXPECT_TRUE(scene.intersect_for_shading(ray, hit));
    ShadedMaterial scratch;
    (void)scene.shade(hit, ray.direction, scratch);
    return hit.shading_normal;
}

float angle_between(const glm::vec3& a, const glm::vec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f));
}

// A scene of the quad (as a mesh, or as an instance placed by `m`) whose material has
// normal map texel `texel` with the given scale.
Scene normal_mapped(TriangleMesh mesh, const glm::vec3& texel, float scale = 1.0f,
                    const glm::mat4* instance = nullptr) {
    Scene scene;
    Material mat = Material::diffuse(glm::vec3(0.5f));
    mat.normal_texture.texture = scene.add_texture(constant(texel));
    mat.normal_scale = scale;
    const std::uint32_t id = scene.add_material(mat);
    if (instance != nullptr)
        (void)scene.add_instance(scene.add_mesh_prototype(std::move(mesh)), *instance, id);
    else
        (void)scene.add_mesh(std::move(mesh), id);
    scene.commit();
    return scene;
}

TEST(NormalMap, FlatTexelLeavesTheInterpolatedNormalBitForBit) {
    // Bent vertex normals, so the interpolated normal is not a round value.
    TriangleMesh mesh = unit_quad();
    mesh.normals = {glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f)),
                    glm::normalize(glm::vec3(-0.1f, 0.25f, 1.0f)),
                    glm::normalize(glm::vec3(0.05f, 0.4f, 1.0f)),
                    glm::normalize(glm::vec3(-0.35f, -0.15f, 1.0f))};
    mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
    Scene plain;
    (void)plain.add_mesh(mesh, plain.add_material(Material::diffuse(glm::vec3(0.5f))));
    plain.commit();
    const Scene mapped = normal_mapped(mesh, {0.5f, 0.5f, 1.0f});
    for (const float x : {-0.77f, -0.2f, 0.013f, 0.61f})
        for (const float y : {-0.9f, -0.33f, 0.25f, 0.8f}) {
            Hit a, b;
            ASSERT_TRUE(plain.intersect_for_shading(Ray({x, y, 2}, {0, 0, -1}), a));
            const glm::vec3 n = shaded_normal(mapped, x, y);
            EXPECT_EQ(n, a.shading_normal) << x << " " << y;  // bit for bit
        }
}

TEST(NormalMap, TiltedTexelTiltsByThePredictedAngleWithGivenTangents) {
    // Tangent-space normal (sin t, 0, cos t) encoded as a texel: tilt t toward the tangent.
    // Tilts below 45 degrees: seen straight down, a steeper normal would mirror the viewer
    // below the surface, and Scene::shade adapts it (adapt_shading_normal).
    for (const float theta : {0.1f, 0.4f, 0.75f}) {
        const glm::vec3 texel(0.5f + 0.5f * std::sin(theta), 0.5f, 0.5f + 0.5f * std::cos(theta));
        TriangleMesh mesh = unit_quad();
        mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
        const glm::vec3 n = shaded_normal(normal_mapped(mesh, texel), 0.3f, -0.4f);
        EXPECT_NEAR(angle_between(n, {0, 0, 1}), theta, 2e-6f);
        EXPECT_NEAR(n.x, std::sin(theta), 2e-6f);  // toward +x, the tangent
        EXPECT_NEAR(n.y, 0.0f, 2e-6f);
        // The y channel tilts toward the bitangent w cross(n, t): +y for w = 1, -y for -1.
        const glm::vec3 ty(0.5f, 0.5f + 0.5f * std::sin(theta), 0.5f + 0.5f * std::cos(theta));
        for (const float w : {1.0f, -1.0f}) {
            mesh.tangents.assign(4, glm::vec4(1, 0, 0, w));
            const glm::vec3 m = shaded_normal(normal_mapped(mesh, ty), -0.5f, 0.5f);
            EXPECT_NEAR(m.y, w * std::sin(theta), 2e-6f) << w;
            EXPECT_NEAR(angle_between(m, {0, 0, 1}), theta, 2e-6f);
        }
    }
    // normalTexture.scale multiplies x and y: tan(tilt) = scale tan(t).
    const float theta = 0.3f, scale = 2.0f;
    TriangleMesh mesh = unit_quad();
    mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
    const glm::vec3 texel(0.5f + 0.5f * std::sin(theta), 0.5f, 0.5f + 0.5f * std::cos(theta));
    const glm::vec3 n = shaded_normal(normal_mapped(mesh, texel, scale), 0.1f, 0.1f);
    EXPECT_NEAR(angle_between(n, {0, 0, 1}), std::atan(scale * std::tan(theta)), 2e-6f);
}

TEST(NormalMap, InstancesCarryTheTangentFrameAndMirrorsFlipTheBitangent) {
    const float theta = 0.5f;
    const glm::vec3 tx(0.5f + 0.5f * std::sin(theta), 0.5f, 0.5f + 0.5f * std::cos(theta));
    const glm::vec3 ty(0.5f, 0.5f + 0.5f * std::sin(theta), 0.5f + 0.5f * std::cos(theta));
    TriangleMesh mesh = unit_quad();
    mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
    // Rotated a quarter turn about z: the tangent is now +y, the bitangent -x.
    const glm::mat4 rot = glm::rotate(glm::mat4(1.0f), float(M_PI / 2), glm::vec3(0, 0, 1));
    glm::vec3 n = shaded_normal(normal_mapped(mesh, tx, 1.0f, &rot), 0.2f, 0.3f);
    EXPECT_NEAR(n.y, std::sin(theta), 2e-6f);
    EXPECT_NEAR(n.x, 0.0f, 2e-6f);
    n = shaded_normal(normal_mapped(mesh, ty, 1.0f, &rot), 0.2f, 0.3f);
    EXPECT_NEAR(n.x, -std::sin(theta), 2e-6f);
    // Mirrored in x: the tangent maps to -x; the mapped bitangent stays +y (the baked
    // copy's), which cross(n, t) alone would get wrong.
    const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
    n = shaded_normal(normal_mapped(mesh, ty, 1.0f, &mirror), 0.2f, 0.3f);
    EXPECT_NEAR(n.y, std::sin(theta), 2e-6f);
    n = shaded_normal(normal_mapped(mesh, tx, 1.0f, &mirror), 0.2f, 0.3f);
    EXPECT_NEAR(n.x, -std::sin(theta), 2e-6f);
}

TEST(NormalMap, GeneratedTangentsFollowTheUvsAndTiltAsPredicted) {
    // OBJ uvs (v up): u along +x, v along +y: tangent +x, w = +1.
    TriangleMesh mesh = unit_quad();
    std::vector<glm::vec4> t = generate_tangents(mesh, false);
    ASSERT_EQ(t.size(), 4u);
    for (const glm::vec4& v : t) {
        EXPECT_NEAR(v.x, 1.0f, 1e-6f);
        EXPECT_NEAR(v.y, 0.0f, 1e-6f);
        EXPECT_EQ(v.w, 1.0f);
    }
    // glTF uvs (v down) for the same picture: v = 1 - v_obj. Same frame.
    TriangleMesh gltf = mesh;
    for (glm::vec2& uv : gltf.uvs) uv.y = 1.0f - uv.y;
    EXPECT_EQ(generate_tangents(gltf, true), t);
    // u running along -y and v along +x (a rotated atlas, with a mirror): tangent -y, and
    // the bitangent +x = w cross(+z, -y) = w (+x): w = +1; mirrored v flips w.
    TriangleMesh turned = unit_quad();
    turned.uvs = {{1, 0}, {1, 1}, {0, 1}, {0, 0}};  // u = (1 - y) / 2, v = (x + 1) / 2
    t = generate_tangents(turned, false);
    for (const glm::vec4& v : t) {
        EXPECT_NEAR(v.y, -1.0f, 1e-6f);
        EXPECT_EQ(v.w, 1.0f);
    }
    for (glm::vec2& uv : turned.uvs) uv.y = 1.0f - uv.y;  // v now along -x
    for (const glm::vec4& v : generate_tangents(turned, false)) EXPECT_EQ(v.w, -1.0f);

    // A tilt through the generated frame, as through given tangents.
    const float theta = 0.7f;
    TriangleMesh m2 = unit_quad();
    m2.tangents = generate_tangents(m2, false);
    const glm::vec3 ty(0.5f, 0.5f + 0.5f * std::sin(theta), 0.5f + 0.5f * std::cos(theta));
    const glm::vec3 n = shaded_normal(normal_mapped(m2, ty), -0.3f, 0.2f);
    EXPECT_NEAR(n.y, std::sin(theta), 2e-6f);
    EXPECT_NEAR(angle_between(n, {0, 0, 1}), theta, 2e-6f);
    // Without normals, the face normal stands in: the same tangents.
    TriangleMesh bare = unit_quad();
    bare.normals.clear();
    EXPECT_EQ(generate_tangents(bare, false).size(), 4u);
    EXPECT_NEAR(generate_tangents(bare, false)[2].x, 1.0f, 1e-6f);
}

// A mesh, or a prototype, added without tangents: the normal-mapped material gets them
// from the uvs (the glTF loader's rule), so the map tilts the normal as through given
// tangents; before, the map was silently ignored for want of a frame.
TEST(NormalMap, MeshesAndInstancesWithoutTangentsGetThemForTheirNormalMap) {
    const float theta = 0.7f;
    const glm::vec3 ty(0.5f, 0.5f + 0.5f * std::sin(theta), 0.5f + 0.5f * std::cos(theta));
    const glm::mat4 quarter_turn(glm::vec4(0, 1, 0, 0), glm::vec4(-1, 0, 0, 0),
                                 glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1));
    const glm::mat4 identity(1.0f);
    for (const glm::mat4* instance :
         {static_cast<const glm::mat4*>(nullptr), &identity, &quarter_turn}) {
        ASSERT_TRUE(unit_quad().tangents.empty());
        const glm::vec3 n =
            shaded_normal(normal_mapped(unit_quad(), ty, 1.0f, instance), 0.2f, 0.3f);
        EXPECT_NEAR(angle_between(n, {0, 0, 1}), theta, 2e-6f);
        // Tilted toward the bitangent (+v): +y on the quad, -x once turned a quarter.
        const glm::vec3 b = instance == &quarter_turn ? glm::vec3(-1, 0, 0) : glm::vec3(0, 1, 0);
        EXPECT_NEAR(glm::dot(n, b), std::sin(theta), 2e-6f);
    }
    // Uvs all one point (a glTF primitive without TEXCOORD reads (0, 0)) give no frame: the
    // map is left out, as on a mesh without uvs, rather than read in an arbitrary frame.
    TriangleMesh flat_uvs = unit_quad();
    flat_uvs.uvs.assign(flat_uvs.positions.size(), glm::vec2(0.0f));
    for (const glm::mat4* instance : {static_cast<const glm::mat4*>(nullptr), &identity})
        EXPECT_EQ(shaded_normal(normal_mapped(flat_uvs, ty, 1.0f, instance), 0.2f, 0.3f),
                  glm::vec3(0, 0, 1));
}

TEST(NormalMap, BentNormalsStayOnTheGeometricSide) {
    const glm::vec3 n(0, 0, 1), g(0, 0, 1);
    // Texels at and past the horizon: x = 1 with z = 0, and z < 0 (below the surface).
    for (const glm::vec3 texel :
         {glm::vec3(1.0f, 0.5f, 0.5f), glm::vec3(1.0f, 0.5f, 0.1f), glm::vec3(0.0f, 0.0f, 0.0f)}) {
        const glm::vec3 m = apply_normal_map(texel, 1.0f, n, {1, 0, 0, 1}, g);
        EXPECT_GE(glm::dot(m, g), kMinNormalMapCosine - 1e-6f);
        EXPECT_NEAR(glm::length(m), 1.0f, 1e-6f);
    }
    // No tangent frame: the normal unchanged.
    EXPECT_EQ(apply_normal_map({1.0f, 0.5f, 0.5f}, 1.0f, n, {0, 0, 0, 1}, g), n);
    EXPECT_EQ(apply_normal_map({1.0f, 0.5f, 0.5f}, 1.0f, n, {0, 0, 2, 1}, g), n);
}

TEST(SurfaceInputs, TexturesMultiplyTheFactorsAndUntexturedMaterialsAreReturnedAsStored) {
    Scene scene;
    Material m = Material::metallic_roughness({0.8f, 0.6f, 0.4f}, 0.5f, 0.8f);
    m.emission = glm::vec3(2.0f);
    m.base_color_texture.texture = scene.add_texture(constant({0.5f, 0.25f, 1.0f}));
    m.metallic_roughness_texture.texture = scene.add_texture(constant({0.9f, 0.5f, 0.25f}));
    m.emission_texture.texture = scene.add_texture(constant({0.25f, 0.5f, 0.75f}));
    const std::uint32_t textured = scene.add_material(m);
    const std::uint32_t plain = scene.add_material(Material::diffuse(glm::vec3(0.3f)));
    (void)scene.add_mesh(unit_quad(), textured);
    TriangleMesh other = unit_quad();
    for (glm::vec3& p : other.positions) p.z -= 1.0f;
    (void)scene.add_mesh(std::move(other), plain);
    scene.commit();
    // A textured emitter is light-sampled (branch emitters: its triangle lights carry the
    // texture; tests/render/emitter_light_test.cpp), one light per triangle.
    EXPECT_EQ(scene.lights().size(), unit_quad().triangles.size());
    EXPECT_FALSE(scene.has_unsampled_emitters());

    Hit hit;
    ASSERT_TRUE(scene.intersect_for_shading(Ray({0.2f, 0.1f, 2}, {0, 0, -1}), hit));
    ShadedMaterial scratch;
    const Material& s = scene.shade(hit, {0, 0, -1}, scratch);
    EXPECT_EQ(s.base_color, glm::vec3(0.8f * 0.5f, 0.6f * 0.25f, 0.4f * 1.0f));
    EXPECT_EQ(s.roughness, 0.8f * 0.5f);  // G
    EXPECT_EQ(s.metallic, 0.5f * 0.25f);  // B
    EXPECT_EQ(s.emission, glm::vec3(2.0f * 0.25f, 2.0f * 0.5f, 2.0f * 0.75f));
    EXPECT_EQ(scene.material(textured).base_color, m.base_color);  // the stored one untouched

    Scene untextured;
    const std::uint32_t id = untextured.add_material(Material::diffuse(glm::vec3(0.3f)));
    (void)untextured.add_mesh(unit_quad(), id);
    untextured.commit();
    ASSERT_TRUE(untextured.intersect_for_shading(Ray({0.2f, 0.1f, 2}, {0, 0, -1}), hit));
    EXPECT_EQ(&untextured.shade(hit, {0, 0, -1}, scratch), &untextured.material(id));
}

TEST(SurfaceInputs, VertexColorsMultiplyTheBaseColourWhereTheHitLands) {
    // Colours at the quad's corners; the hit's barycentrics weigh them.
    TriangleMesh mesh = unit_quad();
    mesh.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 0.5f}, {1, 1, 1, 1}};
    Scene scene;
    const std::uint32_t id =
        scene.add_material(Material::metallic_roughness({0.5f, 0.5f, 0.5f}, 0.0f, 0.5f));
    const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -3));
    (void)scene.add_mesh(mesh, id);
    (void)scene.add_instance(scene.add_mesh_prototype(mesh), shift, id);
    scene.commit();
    // (0.5, -0.5) lies in triangle 0 (corners 0, 1, 2): barycentrics b1 = 0.5, b2 = 0.25.
    const glm::vec4 want = 0.25f * mesh.colors[0] + 0.5f * mesh.colors[1] + 0.25f * mesh.colors[2];
    for (const float z : {2.0f, -2.5f}) {  // the mesh, then (below it) the instance
        Hit hit;
        const Ray ray({0.5f, -0.5f, z}, {0, 0, -1});
        ASSERT_TRUE(scene.intersect_for_shading(ray, hit));
        if (z < 0.0f) {
            ASSERT_NE(hit.instance_id, kInvalidId);
        }
        ShadedMaterial scratch;
        const Material& m = scene.shade(hit, ray.direction, scratch);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.base_color[c], 0.5f * want[c], 1e-6f) << c;
        EXPECT_NEAR(scene.coverage(hit), want.w, 1e-6f);
    }
}

TEST(SurfaceInputs, OneSidedBacksAreBlackAndFrontsAsStored) {
    Scene scene;
    Material m = Material::diffuse(glm::vec3(0.6f));
    m.emission = glm::vec3(1.0f);
    m.double_sided = false;
    (void)scene.add_mesh(unit_quad(), scene.add_material(m));
    scene.commit();
    // A one-sided emitter is light-sampled by one-sided triangle lights (branch emitters).
    ASSERT_EQ(scene.lights().size(), unit_quad().triangles.size());
    for (const Light& l : scene.lights()) EXPECT_TRUE(l.one_sided);
    ShadedMaterial scratch;
    Hit hit;
    ASSERT_TRUE(scene.intersect_for_shading(Ray({0, 0, 2}, {0, 0, -1}), hit));
    const Material& front = scene.shade(hit, {0, 0, -1}, scratch);
    EXPECT_EQ(front.kind, MaterialKind::Diffuse);
    EXPECT_EQ(front.emission, glm::vec3(1.0f));
    ASSERT_TRUE(scene.intersect_for_shading(Ray({0, 0, -2}, {0, 0, 1}), hit));
    const Material& back = scene.shade(hit, {0, 0, 1}, scratch);
    EXPECT_FALSE(back.emits());
    EXPECT_EQ(lobes(back), BsdfLobe::None);
}

// A quad whose left half (u < 0.5) has alpha 0 and right half alpha 1, cut at 0.5, above a
// plain floor at z = -1.
Scene cut_out_scene(std::uint32_t* quad_object) {
    Scene scene;
    const std::vector<std::uint8_t> rgba{255, 255, 255, 0, 255, 255, 255, 255};
    Material leaf = Material::diffuse(glm::vec3(0.5f));
    leaf.base_color_texture.texture = scene.add_texture(ImageTexture::from_rgba8(
        2, 1, rgba, ColorSpace::Srgb,
        {TextureWrap::ClampToEdge, TextureWrap::ClampToEdge, TextureFilter::Nearest}));
    leaf.alpha_cutoff = 0.5f;
    *quad_object = scene.add_mesh(unit_quad(), scene.add_material(leaf));
    TriangleMesh floor = unit_quad();
    for (glm::vec3& p : floor.positions) p = glm::vec3(p.x * 3, p.y * 3, -1.0f);
    (void)scene.add_mesh(std::move(floor), scene.add_material(Material::diffuse(glm::vec3(0.2f))));
    scene.commit();
    return scene;
}

TEST(AlphaMask, RaysPassThroughCutOutTexelsAndStopAtOpaqueOnes) {
    std::uint32_t quad = 0;
    const Scene scene = cut_out_scene(&quad);
    Hit hit;
    // Through the transparent half: the floor behind.
    ASSERT_TRUE(scene.intersect(Ray({-0.5f, 0.3f, 2}, {0, 0, -1}), hit));
    EXPECT_NE(hit.object_id, quad);
    EXPECT_FLOAT_EQ(hit.point.z, -1.0f);
    ASSERT_TRUE(scene.intersect_for_shading(Ray({-0.5f, 0.3f, 2}, {0, 0, -1}), hit));
    EXPECT_NE(hit.object_id, quad);
    // Through the opaque half: the quad.
    ASSERT_TRUE(scene.intersect_for_shading(Ray({0.5f, 0.3f, 2}, {0, 0, -1}), hit));
    EXPECT_EQ(hit.object_id, quad);
    EXPECT_FLOAT_EQ(hit.point.z, 0.0f);
    // Shadow rays that end before the floor: occluded by the opaque half only.
    Ray shadow({-0.5f, 0.3f, 2}, {0, 0, -1});
    shadow.t_max = 2.5f;
    EXPECT_FALSE(scene.occluded(shadow));
    shadow.origin.x = 0.5f;
    EXPECT_TRUE(scene.occluded(shadow));
    EXPECT_FALSE(scene.occluded(shadow, quad));  // the ignored object is skipped
    // Without a texture the factor alone decides: alpha 0.4 < 0.5 cuts everything out.
    Scene faint;
    Material m = Material::diffuse(glm::vec3(0.5f));
    m.alpha = 0.4f;
    m.alpha_cutoff = 0.5f;
    (void)faint.add_mesh(unit_quad(), faint.add_material(m));
    faint.commit();
    EXPECT_FALSE(faint.intersect(Ray({0.1f, 0.1f, 2}, {0, 0, -1}), hit));
    EXPECT_FALSE(faint.occluded(Ray({0.1f, 0.1f, 2}, {0, 0, -1})));
}

}  // namespace
}  // namespace librt
