#include "render/aov.h"

#include <librt/geometry/ray_offset.h>
#include <librt/material/bsdf.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {

namespace {

/// Mixed into the seed so the AOV stream of a sample differs from its integrator stream.
constexpr std::uint64_t kAovStream = 0x41f0'5eed'a0c5'1a7eULL;

}  // namespace

AovSample sample_aovs(const Scene& scene, const Ray& camera_ray, const glm::vec3& forward,
                      std::uint32_t x, std::uint32_t y, std::uint32_t sample, std::uint64_t seed) {
    AovSample out;
    Ray ray = camera_ray;
    // Unit direction, so hit.t is a distance (t's range rescaled to match).
    const float len = glm::length(ray.direction);
    if (!(len > 0.0f) || !std::isfinite(len)) return out;
    ray.direction /= len;
    ray.t_min *= len;
    ray.t_max *= len;
    Pcg32 rng = make_sample_rng(x, y, sample, seed ^ kAovStream);
    glm::vec3 tint(1.0f);
    ShadedMaterial shaded;
    for (int bounce = 0; bounce <= kAovMaxSpecularBounces; ++bounce) {
        Hit hit;
        bool found = scene.intersect_for_shading(ray, hit);
        // The camera ray passes what the path tracer's does (hidden objects, culled backs;
        // bounded as there).
        for (int passed = 0; found && bounce == 0 && scene.camera_may_pass() &&
                             scene.camera_passes(hit, ray.direction);
             ++passed) {
            if (passed >= 64) return out;
            ray = spawn_ray(hit, ray.direction);
            found = scene.intersect_for_shading(ray, hit);
        }
        if (!found) return out;  // escaped: albedo 0
        if (bounce == 0) {
            out.hit = true;
            // Planar depth: every camera ray starts on the lens plane (camera.h), so the
            // hit's depth along the optical axis from that plane is t cos(ray, axis).
            out.depth = hit.t * glm::dot(ray.direction, forward);
        }
        // Textures, vertex colours and the normal map applied, as the integrators see them.
        const Material& m = scene.shade(hit, ray.direction, shaded);
        if (bounce == 0 && m.emits()) {
            const std::uint32_t light = scene.light_of_hit(hit);
            const bool back = light != kInvalidId && scene.lights()[light].one_sided &&
                              !(glm::dot(ray.direction, hit.geometric_normal) < 0.0f);
            if (!back) out.emission = m.emission;
        }
        const BsdfLobe lobe_flags = lobes(m);
        // The per-hit albedo every lobe is scaled by (bsdf.h), as the path loop takes it.
        const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
        const ShadingPoint sp{
            ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction), albedo};
        if (!has(lobe_flags, BsdfLobe::Specular) || has_non_specular(lobe_flags)) {
            // The first surface that is not purely specular: what its BSDF reflects or
            // transmits (emitters, no lobes: 0), tinted by the way here.
            // Times the material's ambient occlusion map (glTF occlusionTexture), which
            // only this guide sees: the beauty's occlusion is the path tracer's own.
            out.albedo = tint * denoising_albedo(m, sp) * scene.occlusion(hit);
            out.normal = hit.shading_normal;
            return out;
        }
        // Through a mirror or glass, as the path tracer goes: by the BSDF seam's sample.
        const float uc = chooses_lobe(lobe_flags) ? rng.next_float() : 0.0f;
        const BsdfSample bs =
            librt::sample(m, sp, sp.frame.to_local(-ray.direction), uc, glm::vec2(0.5f));
        if (!bs.valid()) return out;
        // A specular lobe chosen with probability pdf has weight tint * pdf / pdf = tint.
        tint *= bs.weight;
        ray = spawn_ray(hit, sp.frame.to_world(bs.wi));
    }
    return out;  // too many specular bounces: albedo 0
}

}  // namespace librt
