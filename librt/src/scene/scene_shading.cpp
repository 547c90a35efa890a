// The Scene's per-hit material inputs (textures, normal maps, one-sided backs) and the
// alpha test of cut-out materials; kept out of scene.cpp, and out of line, so a scene
// without them pays one predictable branch per query.

#include "material/bsdf_dispatch.h"

#include <librt/material/bsdf.h>
#include <librt/material/normal_map.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <new>

namespace librt {

glm::vec3 apply_normal_map(const glm::vec3& texel, float scale, const glm::vec3& n,
                           const glm::vec4& tangent, const glm::vec3& geometric) {
    // glTF 2.0 sec. 3.9.3: the texel maps to [-1, 1]; normalTexture.scale scales x and y.
    const float x = (2.0f * texel.x - 1.0f) * scale, y = (2.0f * texel.y - 1.0f) * scale;
    const float z = 2.0f * texel.z - 1.0f;
    if (x == 0.0f && y == 0.0f) return n;  // flat: the interpolated normal, unchanged
    // Gram-Schmidt: the tangent's part perpendicular to n.
    const glm::vec3 t_raw = glm::vec3(tangent) - glm::dot(n, glm::vec3(tangent)) * n;
    const float t_len = glm::length(t_raw);
    if (!(t_len > 1e-12f) || !std::isfinite(t_len)) return n;
    const glm::vec3 t = t_raw / t_len;
    const glm::vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, t);
    glm::vec3 m = x * t + y * b + z * n;
    float len = glm::length(m);
    if (!(len > 0.0f) || !std::isfinite(len)) return n;
    m /= len;
    // Keep it on the geometric side (see kMinNormalMapCosine): lean it toward the
    // geometric normal by what its cosine lacks.
    const float c = glm::dot(m, geometric);
    if (c < kMinNormalMapCosine) {
        m += (kMinNormalMapCosine - c) * geometric;
        len = glm::length(m);
        if (!(len > 0.0f)) return n;
        m /= len;
    }
    return m;
}

glm::vec3 adapt_shading_normal(const glm::vec3& n, const glm::vec3& g, const glm::vec3& wo) {
    // On wo's side: the hit gives n and g on the primitive's side, wherever the ray came from.
    const float side = glm::dot(wo, g) < 0.0f ? -1.0f : 1.0f;
    const glm::vec3 gs = side * g, ns = side * n;
    const glm::vec3 r = 2.0f * glm::dot(wo, ns) * ns - wo;
    const float rg = glm::dot(r, gs);
    if (rg >= kMinMirrorCosine) return n;
    // r's part along the surface, then r pulled up to the least cosine in r's azimuth (wo's
    // own azimuth, mirrored, when r has none: straight back along the surface from wo).
    glm::vec3 t = r - rg * gs;
    float len = glm::length(t);
    if (!(len > 1e-6f)) {
        t = -(wo - glm::dot(wo, gs) * gs);
        len = glm::length(t);
        if (!(len > 1e-6f)) return side * gs;  // wo along g: the geometric normal mirrors it
    }
    const float c = kMinMirrorCosine;
    const glm::vec3 r2 = std::sqrt(1.0f - c * c) * (t / len) + c * gs;
    // wo and r2 both above the surface, so their sum is not zero.
    const glm::vec3 h = glm::normalize(wo + r2);
    return side * h;
}

glm::vec2 Scene::slot_uv(const TextureSlot& slot, const Hit& hit) const {
    return slot.uv_set == 1 ? top_.uv1(hit) : hit.uv;
}

glm::vec3 Scene::occlusion(const Hit& hit) const {
    const Material& m = material(hit);
    if (!m.occlusion_texture.bound()) return glm::vec3(1.0f);
    const TextureSlot& s = m.occlusion_texture;
    const float r = textures_[std::size_t(s.texture)].lookup(s.map(slot_uv(s, hit))).x;
    return glm::vec3(1.0f + m.occlusion_strength * (std::clamp(r, 0.0f, 1.0f) - 1.0f));
}

const Material& Scene::shade_varying(Hit& hit, const glm::vec3& direction,
                                     ShadedMaterial& scratch) const {
    const Material& stored = material(hit);
    const bool colored = top_.has_colors(hit.object_id);
    if (!stored.varies_per_hit() && !colored) return stored;
    if (!stored.double_sided && !(glm::dot(direction, hit.geometric_normal) < 0.0f)) {
        // The back of a one-sided surface: absorbs, emits nothing.
        return *new (&scratch.material_) Material(Material::emissive(glm::vec3(0.0f)));
    }
    // Material is trivially copyable and destructible: a new copy over the last one.
    Material& m = *new (&scratch.material_) Material(stored);
    const auto lookup = [&](const TextureSlot& s) {
        return textures_[std::size_t(s.texture)].lookup(s.map(slot_uv(s, hit)));
    };
    if (m.base_color_texture.bound()) m.base_color *= lookup(m.base_color_texture);
    if (colored) {
        // glTF COLOR_0 multiplies the material's colour: the base colour of a glTF
        // material, the albedo of librt's other kinds (each kind says which).
        bsdfs::multiply_color(m, glm::clamp(glm::vec3(top_.color(hit)), 0.0f, 1.0f));
    }
    if (m.metallic_roughness_texture.bound()) {
        // glTF: roughness in the green channel, metalness in the blue one (both linear).
        const glm::vec3 mr = lookup(m.metallic_roughness_texture);
        m.roughness *= mr.y;
        m.metallic *= mr.z;
    }
    if (m.emission_texture.bound()) m.emission *= lookup(m.emission_texture);
    // An unlit surface emits its base colour (texture and vertex colour applied above).
    if (m.unlit) m.emission = m.base_color;
    // KHR_materials_clearcoat: the factor in the red channel, the roughness in the green.
    if (m.clearcoat_texture.bound()) m.clearcoat *= lookup(m.clearcoat_texture).x;
    if (m.clearcoat_roughness_texture.bound())
        m.clearcoat_roughness *= lookup(m.clearcoat_roughness_texture).y;
    // KHR_materials_sheen and _specular: colours in RGB (sRGB), the scalars in alpha;
    // KHR_materials_transmission: the factor in the red channel.
    const auto lookup_alpha = [&](const TextureSlot& s) {
        return textures_[std::size_t(s.texture)].lookup_alpha(s.map(slot_uv(s, hit)));
    };
    if (m.sheen_color_texture.bound()) m.sheen_color *= lookup(m.sheen_color_texture);
    if (m.sheen_roughness_texture.bound())
        m.sheen_roughness *= lookup_alpha(m.sheen_roughness_texture);
    if (m.specular_texture.bound()) m.specular *= lookup_alpha(m.specular_texture);
    if (m.specular_color_texture.bound()) m.specular_color *= lookup(m.specular_color_texture);
    if (m.transmission_texture.bound()) m.transmission *= lookup(m.transmission_texture).x;
    // KHR_materials_clearcoat's clearcoatNormalTexture: the coat's own normal, bent from
    // the interpolated normal (before normal_texture bends the base's) and adapted to the
    // viewer as the base's is.
    if (m.clearcoat_normal_texture.bound() && m.clearcoat > 0.0f) {
        const glm::vec3 n =
            apply_normal_map(lookup(m.clearcoat_normal_texture), m.clearcoat_normal_scale,
                             hit.shading_normal, top_.tangent(hit), hit.geometric_normal);
        m.clearcoat_normal = adapt_shading_normal(n, hit.geometric_normal, -direction);
    }
    if (m.normal_texture.bound()) {
        const glm::vec4 t = top_.tangent(hit);
        hit.shading_normal = apply_normal_map(lookup(m.normal_texture), m.normal_scale,
                                              hit.shading_normal, t, hit.geometric_normal);
        // No viewer sees the mapped normal turned away from it (docs/robustness.md).
        hit.shading_normal =
            adapt_shading_normal(hit.shading_normal, hit.geometric_normal, -direction);
    }
    if (m.anisotropy > 0.0f) anisotropy_at(hit, m);
    // KHR_materials_volume: a ray reaching a closed surface's back ran inside it for hit.t
    // (from the surface it entered by); whatever the surface then does, reflect back in or
    // leave, carries that segment's Beer-Lambert transmittance, as its albedo scales every lobe.
    if (m.absorbs_inside() && glm::dot(direction, hit.geometric_normal) > 0.0f)
        m.albedo *= m.interior_transmittance(hit.t * glm::length(direction));
    return m;
}

void Scene::anisotropy_at(const Hit& hit, Material& m) const {
    // KHR_materials_anisotropy: the direction (cos r, sin r) in tangent-bitangent space, or
    // the texture's RG direction turned by r; the texture's B scales the strength.
    float c = std::cos(m.anisotropy_rotation), s = std::sin(m.anisotropy_rotation);
    if (m.anisotropy_texture.bound()) {
        const TextureSlot& slot = m.anisotropy_texture;
        const glm::vec3 tex =
            textures_[std::size_t(slot.texture)].lookup(slot.map(slot_uv(slot, hit)));
        m.anisotropy *= std::clamp(tex.z, 0.0f, 1.0f);
        const float x = 2.0f * tex.x - 1.0f, y = 2.0f * tex.y - 1.0f;
        const float len = std::sqrt(x * x + y * y);
        if (len > 0.0f) {
            // The rotation applied to the texture's direction: angle sum.
            const float cx = x / len, sy = y / len;
            const float c2 = c * cx - s * sy, s2 = s * cx + c * sy;
            c = c2;
            s = s2;
        }
    }
    // The surface's tangent (increasing u) and bitangent: a mesh's tangents, else a
    // sphere's dP/du (east about +y: u is the azimuth around +y) with b = n x t.
    const glm::vec3& n = hit.shading_normal;
    glm::vec3 t(0.0f);
    float handedness = 1.0f;
    const glm::vec4 tangent = top_.tangent(hit);
    if (tangent != glm::vec4(0.0f)) {
        t = glm::vec3(tangent);
        handedness = tangent.w < 0.0f ? -1.0f : 1.0f;
    } else if (top_.kind(hit.object_id) == ObjectKind::Sphere) {
        t = {-hit.geometric_normal.z, 0.0f, hit.geometric_normal.x};
    }
    // Gram-Schmidt onto the shading plane; none (a pole, or a mesh without uvs): zero, and
    // the BSDFs use their frame's own x axis.
    t -= glm::dot(n, t) * n;
    const float len = glm::length(t);
    if (!(len > 1e-12f) || !std::isfinite(len)) {
        m.anisotropy_direction = glm::vec3(0.0f);
        return;
    }
    t /= len;
    const glm::vec3 b = handedness * glm::cross(n, t);
    m.anisotropy_direction = c * t + s * b;
}

float Scene::coverage(const Hit& hit) const {
    const Material& m = material(hit);
    float a = m.alpha * std::clamp(top_.color(hit).w, 0.0f, 1.0f);
    if (m.base_color_texture.bound()) {
        const TextureSlot& s = m.base_color_texture;
        a *= textures_[std::size_t(s.texture)].lookup_alpha(s.map(slot_uv(s, hit)));
    }
    return a;
}

namespace {

// A 64-bit mix of one more word into h (the multiply-xorshift finalizer of MurmurHash3's
// fmix64 after a golden-ratio step): every input bit reaches every output bit.
std::uint64_t mix(std::uint64_t h, std::uint64_t word) {
    h ^= word + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
}

// A number in [0, 1) for the stochastic opacity of `hit` on `ray`: a hash of both, so it
// is the same each time the ray is asked (a closest-hit query and an any-hit one agree),
// independent of threads, and independent between surfaces along the ray (t and the
// primitive differ) and between the rays of different samples.
float coverage_number(const Ray& ray, const Hit& hit) {
    const auto bits = [](float f) { return std::uint64_t(std::bit_cast<std::uint32_t>(f)); };
    std::uint64_t h = 0x5bd1e995u;
    h = mix(h, bits(ray.origin.x) | bits(ray.origin.y) << 32);
    h = mix(h, bits(ray.origin.z) | bits(ray.direction.x) << 32);
    h = mix(h, bits(ray.direction.y) | bits(ray.direction.z) << 32);
    h = mix(h, std::uint64_t(hit.object_id) | std::uint64_t(hit.primitive_id) << 32);
    h = mix(h, std::uint64_t(hit.instance_id) | bits(hit.t) << 32);
    return float(h >> 40) * 0x1p-24f;
}

}  // namespace

bool Scene::in_cut_out_hole(const Ray& ray, const Hit& hit) const {
    const Material& m = material(hit);
    if (!m.cuts_out()) return false;
    // Partial coverage a: opaque for a number below a (probability a), a hole otherwise.
    if (m.alpha_blend) return !(coverage_number(ray, hit) < coverage(hit));
    return coverage(hit) < m.alpha_cutoff;
}

bool Scene::camera_passes(const Hit& hit, const glm::vec3& direction) const {
    if (!camera_visible(hit.object_id)) return true;
    // Back-face culling: the back of a one-sided surface (as shade_varying tells it).
    return one_sided_ && !(glm::dot(direction, hit.geometric_normal) < 0.0f) &&
           !material(hit).double_sided;
}

bool Scene::intersect_carefully(const Ray& ray, Hit& hit, bool every_sphere_uv) const {
    Hit h;
    if (cut_outs_ ? !intersect_past_cut_outs(ray, h) : !top_.intersect(ray, h, every_sphere_uv))
        return false;
    if (pass_through_surfaces_ && may_pass_through(material(h))) surface_under_pane(ray, h);
    hit = h;
    return true;
}

bool Scene::intersect_geometric_carefully(const Ray& ray, GeometricHit& hit) const {
    Hit h;
    if (!intersect_carefully(ray, h, true)) return false;
    hit.t = h.t;
    hit.geometric_normal = h.geometric_normal;
    hit.primitive_id = h.primitive_id;
    hit.object_id = h.object_id;
    hit.instance_id = h.instance_id;
    return true;
}

// A pane lying on another surface (cornell_pbr.glb's glass cube, its bottom in the floor's
// plane) meets a ray at the same t as that surface, give or take rounding, and which one
// the query returns is chance. Crossing the pane then restarts the ray past its plane, so
// the surface was lost (the floor inside that cube rendered at half its brightness): the
// other surface is taken instead, as if the pane were not there. 1e-5 of t covers the
// rounding of two hits on one plane, far below any gap a scene means.
void Scene::surface_under_pane(const Ray& ray, Hit& pane) const {
    const float slack = 1e-5f * pane.t;
    Ray probe = ray;
    probe.t_min = std::max(ray.t_min, pane.t - slack);
    probe.t_max = std::min(ray.t_max, pane.t + slack);
    Hit under;
    if (!top_.intersect_ignoring(probe, under, pane.object_id, true)) return;
    if (cut_outs_ && in_cut_out_hole(probe, under)) return;
    pane = under;
}

bool Scene::intersect_past_cut_outs(const Ray& ray, Hit& hit) const {
    Ray r = ray;
    Hit h;
    // Each pass starts past the last hole (t_min is exclusive), so t grows strictly and
    // the loop ends within the number of surfaces along the ray. Every sphere's uv is
    // computed: the alpha test reads it.
    while (top_.intersect(r, h, true)) {
        if (!in_cut_out_hole(r, h)) {
            hit = h;
            return true;
        }
        r.t_min = h.t;
    }
    return false;
}

bool Scene::occluded_past_cut_outs(const Ray& ray, std::uint32_t ignored_object) const {
    Ray r = ray;
    Hit h;
    while (top_.intersect(r, h, true)) {
        if (h.object_id != ignored_object && !in_cut_out_hole(r, h)) return true;
        r.t_min = h.t;
    }
    return false;
}

}  // namespace librt
