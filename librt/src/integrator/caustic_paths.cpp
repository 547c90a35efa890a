// The light half of caustic light paths (caustic_paths.h): one light path per camera
// sample through caustic casters, joined to the lens where it lands on another surface.

#include "integrator/caustic_paths.h"

#include "film/camera_importance.h"
#include "geometry/ray_copy.h"
#include "integrator/light_path_start.h"
#include "integrator/mis.h"
#include "integrator/shading_correction.h"
#include "integrator/transmittance.h"
#include "material/bsdf_dispatch.h"
#include "scene/shadow_ray.h"

#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/light/light.h>
#include <librt/material/bsdf.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt {
namespace {

/// Sampler dimensions of the light path: light choice (1D), origin (2D), direction (2D),
/// then per caster vertex j kPerCaster: lobe (1D), direction (2D), roulette (1D); the
/// lens point of the join (2D) takes the slot of the vertex after the last caster. Far above the
/// camera path's bounces (below 7 * 1001) and below its crossing decisions
/// (SampleDimensions::kPassThrough).
constexpr std::uint32_t kBase = 1u << 15u;
constexpr std::uint32_t kFirstCaster = kBase + 5;
constexpr std::uint32_t kPerCaster = 4;
/// Casters never rouletted: a chain of mirrors facing each other must still end soon.
constexpr int kRouletteAfter = 3;
/// The light path's crossing decisions follow the camera path's (kMaxCrossingDecisions
/// bounds both): from here, so no number is drawn twice in one sample.
constexpr std::uint32_t kFirstDecision = kMaxCrossingDecisions / 2;

}  // namespace

void splat_caustic_path(const Scene& scene, const SceneSphere& sphere, const Camera& camera,
                        SplatFilm& film, Sampler& sampler, int max_depth, float max_roughness) {
    // E D G L has two scattering events at least.
    if (max_depth < 2) return;
    const LightSampler& lights = scene.light_sampler();
    if (!lights.any()) return;
    // Lights at infinity start no path: their caustics stay with the camera path.
    const LightPathStart start = start_light_path(scene, sphere, sampler, kBase);
    if (!start.valid) return;
    const LightLeSample& le = start.le;
    // Throughput Le |cos| / (p_choice p_pos p_dir), as a light subpath of bdpt.cpp starts.
    glm::vec3 beta = le.radiance * (start.cosine() / (start.chosen.pmf * le.pdf_pos * le.pdf_dir));
    Ray ray = start.ray();

    std::uint32_t decisions = kFirstDecision;
    int casters = 0;             // caster vertices so far
    glm::vec3 throughput(1.0f);  // what the casters let through, for roulette
    Hit hit;
    ShadedMaterial shaded;
    for (;;) {
        if (!scene.intersect_for_shading(ray, hit)) return;
        const Material& m = scene.shade(hit, ray.direction, shaded);
        const BsdfLobe lobes = bsdfs::lobes_of(m);
        if (has(lobes, BsdfLobe::Null)) {
            // Crossed as PathTracer crosses it; a crossing is no vertex.
            const Crossing x = cross_null(scene, m, hit, ray.direction, sampler, decisions++);
            beta *= x.weight;
            if (x.crossed) {
                if (decisions > kMaxCrossingDecisions) return;
                detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, ray.direction);
                continue;
            }
        }
        if (lobes == BsdfLobe::None) return;
        const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
        const ShadingPoint sp{
            ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction), albedo};
        const glm::vec3 wo = -ray.direction;  // toward the light's side
        const glm::vec3 wo_local = sp.frame.to_local(wo);
        const auto j = static_cast<std::uint32_t>(casters);
        if (!casts_caustics(m, max_roughness)) {
            // The seen surface D: a caustic only after a caster (else it is direct light,
            // the camera path's).
            if (casters == 0) return;
            sampler.set_dimension(kFirstCaster + j * kPerCaster);
            const glm::vec2 u_lens = sampler.next_2d();
            const CameraWi cw = sample_wi(camera, hit.point, u_lens, film.margin());
            if (!cw.valid) return;
            const glm::vec3 f =
                bsdfs::eval_bsdf(m, sp, wo_local, sp.frame.to_local(cw.wi)) *
                shading_correction(hit.shading_normal, hit.geometric_normal, wo, cw.wi);
            // Film estimate beta f |cos| We cos_lens / d^2 (camera_importance.h).
            glm::vec3 contrib =
                beta * f * (std::fabs(glm::dot(hit.shading_normal, cw.wi)) * cw.weight);
            if (!(max_component(contrib) > 0.0f)) return;
            contrib *= lens_transmittance(
                scene, spawn_ray_between(hit.point, hit.geometric_normal, hit.offset, cw.view_start,
                                         glm::vec3(0.0f), 0.0f));
            if (!(max_component(contrib) > 0.0f)) return;
            film.add(cw.raster, contrib);
            return;
        }
        // A caster: room for it and for the surface it lights (max_depth events in all).
        if (casters + 2 > max_depth) return;
        sampler.set_dimension(kFirstCaster + j * kPerCaster);
        const float uc = sampler.next_1d();
        sampler.set_dimension(kFirstCaster + j * kPerCaster + 1);
        const glm::vec2 u = sampler.next_2d();
        const BsdfSample bs = bsdfs::sample_bsdf(m, sp, wo_local, uc, u);
        if (!bs.valid()) return;
        const glm::vec3 wi = sp.frame.to_world(bs.wi);
        const glm::vec3 scatter =
            bs.weight * shading_correction(hit.shading_normal, hit.geometric_normal, wo, wi);
        beta *= scatter;
        throughput *= scatter;
        if (!(max_component(beta) > 0.0f)) return;
        ++casters;
        if (casters > kRouletteAfter) {
            // Survive with probability q, reweighted by 1 / q: unbiased, and bounded.
            const float q = std::min(0.95f, max_component(throughput));
            sampler.set_dimension(kFirstCaster + j * kPerCaster + 3);
            if (!(q > 0.0f) || sampler.next_1d() >= q) return;
            beta /= q;
            throughput /= q;
        }
        detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, wi);
    }
}

}  // namespace librt
