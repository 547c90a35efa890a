#include "render/aov.h"

#include "geometry/spawn_ray.h"
#include "integrator/transmittance.h"

#include <librt/geometry/ray_offset.h>
#include <librt/light/light.h>
#include <librt/material/bsdf.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {

namespace {

/// Mixed into the seed so the AOV stream of a sample differs from its integrator stream.
constexpr std::uint64_t kAovStream = 0x41f0'5eed'a0c5'1a7eULL;

/// AovSample::visibility at `hit`, reached along unit direction `incoming`: one light
/// chosen by power and a point on it, as the path tracer's next-event estimation draws
/// them (integrators.cpp, sample_direct), but from the AOV's own stream; its shadow ray
/// ends on the light as the path tracer's does (the light's own surface skipped).
// Out of line: callgrind then counts its cost apart (the one extra ray the AOVs trace).
[[gnu::noinline]] float light_visibility(const Scene& scene, const Hit& hit,
                                         const glm::vec3& incoming, Pcg32& rng) {
    const LightSampler& lights = scene.light_sampler();
    const float u_light = rng.next_float();
    const glm::vec2 u(rng.next_float(), rng.next_float());
    const SampledLight chosen = lights.sample(u_light);
    if (!chosen.valid()) return 1.0f;  // no lights: nothing to shadow
    const Light& light = scene.lights()[chosen.light];
    const LightLiSample s = sample_li(light, hit.point, u);
    if (!s.valid()) return 1.0f;
    // The light behind the surface, on the side the camera does not see: it lights
    // nothing here (what a shadow does), whatever lies between.
    const glm::vec3 facing = glm::dot(incoming, hit.geometric_normal) < 0.0f
                                 ? hit.geometric_normal
                                 : -hit.geometric_normal;
    if (!(glm::dot(s.wi, facing) > 0.0f)) return 0.0f;
    const Ray shadow =
        spawn_ray_to(hit.point, hit.geometric_normal, hit.offset, s.wi, s.distance, s.end_slope);
    const glm::vec3 t = shadow_transmittance(scene, shadow, light.object);
    return (t.x + t.y + t.z) / 3.0f;
}

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
            // An emitter seen first keeps 1: its pixels are its emission, not shadowed.
            if (!(bounce == 0 && m.emits()))
                out.visibility = light_visibility(scene, hit, ray.direction, rng);
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
