#include <librt/core/error.h>
#include <librt/render/integrators.h>
#include <librt/render/scatter.h>
#include <librt/render/scene.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <string>

namespace librt {
namespace {

constexpr int kMaxDepthLimit = 1000;

void check_depth(const char* name, int value, int lo, int hi) {
    if (value < lo || value > hi)
        throw Error(std::string(name) + " = " + std::to_string(value) + ": must be in [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

void check(const PathTracerSettings& s) {
    check_depth("max_depth", s.max_depth, 0, kMaxDepthLimit);
    check_depth("russian_roulette_depth", s.russian_roulette_depth, 0, kMaxDepthLimit);
}

float max_component(const glm::vec3& v) { return std::max(std::max(v.x, v.y), v.z); }

/// Which of the report's algorithms a path follows.
enum class Strategy {
    Direct,  ///< light sampling at the first diffuse hit, then stop
    Path,    ///< light sampling plus cosine bounces
    Brute,   ///< cosine bounces only; emitters found by chance
};

/// The shadow ray from surface point p toward `target`, when the target is in front of
/// both the geometric normal ng and the shading normal ns; also gives the shading cosine
/// and the squared distance. Starts off the surface along ng; ends at the target.
std::optional<Ray> shadow_ray_to(const glm::vec3& p, const glm::vec3& ng, const glm::vec3& ns,
                                 const glm::vec3& target, float& cos_s, float& d2) {
    const glm::vec3 to_light = target - p;
    d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f)) return std::nullopt;
    const glm::vec3 wl = to_light / std::sqrt(d2);
    cos_s = glm::dot(ns, wl);
    if (cos_s <= 0.0f || glm::dot(ng, wl) <= 0.0f) return std::nullopt;
    Ray shadow;
    shadow.origin = offset_ray_origin(p, ng, wl);
    const glm::vec3 rest = target - shadow.origin;
    shadow.t_max = glm::length(rest);
    if (!(shadow.t_max > 0.0f)) return std::nullopt;
    shadow.direction = rest / shadow.t_max;
    return shadow;
}

/// The sum over all lights of one estimate each of L_i cos(theta) / pdf, i.e. of the
/// irradiance at a point with unit normals ng (geometric) and ns (shading), both on the
/// side the light must come from. Shadow rays start off the surface along ng.
glm::vec3 light_irradiance(const Scene& scene, const glm::vec3& p, const glm::vec3& ng,
                           const glm::vec3& ns, Sampler& sampler) {
    glm::vec3 e(0.0f);
    for (const PointLight& light : scene.point_lights()) {
        float cos_s = 0.0f, d2 = 0.0f;
        const std::optional<Ray> shadow = shadow_ray_to(p, ng, ns, light.position, cos_s, d2);
        if (!shadow || scene.occluded(*shadow)) continue;
        // Irradiance from a point light: E = I cos(theta) / d^2.
        e += light.intensity * (cos_s / d2);
    }
    const auto lights = scene.sphere_lights();
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const SphereLight& light = lights[i];
        // Drawn even when unused, so later decisions of the path keep their numbers.
        const glm::vec2 u = sampler.next_2d();
        const SphereDirectionSample s =
            sample_sphere_direction(light.sphere.center, light.sphere.radius, p, u);
        if (!(s.pdf > 0.0f)) continue;
        const float cos_w = glm::dot(ns, s.direction);
        if (cos_w <= 0.0f || glm::dot(ng, s.direction) <= 0.0f) continue;
        // The shadow ray ends where the direction meets the light. Its start moved off the
        // surface by the offset, so it may reach that far inside the light: harmless, as
        // the light's own sphere is skipped and nothing else should sit in it.
        Ray shadow;
        shadow.origin = offset_ray_origin(p, ng, s.direction);
        shadow.direction = s.direction;
        shadow.t_max = s.distance;
        if (scene.occluded(shadow, scene.sphere_light_object(i))) continue;
        // Monte Carlo irradiance estimate from a solid-angle sample: L cos(theta) / pdf.
        e += light.radiance * (cos_w / s.pdf);
    }
    return e;
}

/// One path from `camera_ray` following `S`; see the class comments in integrators.h.
template <Strategy S>
glm::vec3 trace(const Scene& scene, const Ray& camera_ray, Sampler& sampler, int max_depth,
                bool russian_roulette, int roulette_depth) {
    glm::vec3 radiance(0.0f);
    glm::vec3 throughput(1.0f);
    Ray ray = camera_ray;
    // Work with unit directions (the scattering formulas need them); rescale t's range.
    const float len = glm::length(ray.direction);
    if (!(len > 0.0f) || !std::isfinite(len)) return radiance;
    ray.direction /= len;
    ray.t_min *= len;
    ray.t_max *= len;
    bool emission_counts = true;  // at the camera and after mirrors and glass
    for (int depth = 0;;) {
        Hit hit;
        if (!scene.intersect_for_shading(ray, hit)) break;
        const Material& m = scene.material(hit);
        if (m.emits() &&
            (S == Strategy::Brute || emission_counts || !scene.is_sphere_light(hit.object_id)))
            radiance += throughput * m.emission;
        if (depth >= max_depth || m.kind == MaterialKind::Emissive) break;
        ++depth;

        const glm::vec3& d = ray.direction;
        // Normals turned to the side the ray arrives from.
        const bool front = glm::dot(d, hit.geometric_normal) < 0.0f;
        const glm::vec3 ng = front ? hit.geometric_normal : -hit.geometric_normal;
        const glm::vec3 ns = front ? hit.shading_normal : -hit.shading_normal;
        glm::vec3 wi;
        switch (m.kind) {
            case MaterialKind::Mirror: {
                wi = reflect(d, ns);
                if (glm::dot(wi, ng) <= 0.0f) wi = reflect(d, ng);  // shading normal too bent
                throughput *= m.albedo;
                emission_counts = true;
                break;
            }
            case MaterialKind::Dielectric: {
                const float u = m.fresnel ? sampler.next_1d() : 0.0f;
                DielectricScatter sc =
                    scatter_dielectric(d, hit.shading_normal, m.ior, m.fresnel, u);
                // The shading normal must agree with the geometry about which side the new
                // direction is on; if not, scatter about the geometric normal.
                if (sc.transmitted == (glm::dot(sc.direction, ng) > 0.0f))
                    sc = scatter_dielectric(d, hit.geometric_normal, m.ior, m.fresnel, u);
                wi = sc.direction;
                throughput *= m.albedo;
                emission_counts = true;
                break;
            }
            case MaterialKind::Diffuse: {
                // Everything this vertex adds or passes on is scaled by throughput * albedo:
                // when that is 0 (the blue floor's path meeting the red wall), stop without
                // spending shadow rays on it.
                const glm::vec3 weight = throughput * scene.albedo(hit);
                if (!(max_component(weight) > 0.0f)) return radiance;
                if constexpr (S != Strategy::Brute) {
                    // Lambert: outgoing radiance = albedo / pi * irradiance.
                    radiance +=
                        weight * k_inv_pi * light_irradiance(scene, hit.point, ng, ns, sampler);
                }
                if constexpr (S == Strategy::Direct) {
                    return radiance;
                } else {
                    // The last bounce: what it finds would count only if it emitted and
                    // light sampling had not covered it (this vertex just sampled the
                    // lights). With no such emitter, save the ray.
                    if (S == Strategy::Path && depth >= max_depth &&
                        !scene.has_unsampled_emitters())
                        return radiance;
                    wi = sample_cosine_hemisphere(ns, sampler.next_2d());
                    // Below the true surface (a bent shading normal): the path ends there.
                    if (glm::dot(wi, ng) <= 0.0f) return radiance;
                    // Cosine sampling: (albedo / pi) cos / (cos / pi) = albedo.
                    throughput = weight;
                    emission_counts = false;
                    break;
                }
            }
            case MaterialKind::Emissive:
                return radiance;  // unreachable: handled above
        }
        if (russian_roulette && depth >= roulette_depth) {
            // Survive with probability q, reweighted by 1/q: unbiased, fewer long paths.
            const float q = std::min(0.95f, max_component(throughput));
            if (!(q > 0.0f) || sampler.next_1d() >= q) break;
            throughput /= q;
        }
        if (!(max_component(throughput) > 0.0f)) break;
        ray = spawn_ray(hit.point, hit.geometric_normal, wi);
    }
    return radiance;
}

}  // namespace

glm::vec3 GuardedIntegrator::guard(const glm::vec3& radiance) const {
    if (std::isfinite(radiance.x) && std::isfinite(radiance.y) && std::isfinite(radiance.z))
        return radiance;
    nonfinite_.fetch_add(1, std::memory_order_relaxed);
    assert(false && "integrator produced a non-finite sample");
    return glm::vec3(0.0f);
}

DirectLighting::DirectLighting(const DirectLightingSettings& settings) : settings_(settings) {
    check_depth("max_depth", settings.max_depth, 0, kMaxDepthLimit);
}

glm::vec3 DirectLighting::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    return guard(trace<Strategy::Direct>(scene, ray, sampler, settings_.max_depth, false, 0));
}

PathTracer::PathTracer(const PathTracerSettings& settings) : settings_(settings) {
    check(settings);
}

glm::vec3 PathTracer::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    return guard(trace<Strategy::Path>(scene, ray, sampler, settings_.max_depth,
                                       settings_.russian_roulette,
                                       settings_.russian_roulette_depth));
}

BruteForcePathTracer::BruteForcePathTracer(const PathTracerSettings& settings)
    : settings_(settings) {
    check(settings);
}

glm::vec3 BruteForcePathTracer::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    return guard(trace<Strategy::Brute>(scene, ray, sampler, settings_.max_depth,
                                        settings_.russian_roulette,
                                        settings_.russian_roulette_depth));
}

glm::vec3 AlbedoNormalIntegrator::li(const Scene& scene, const Ray& ray,
                                     Sampler& /*sampler*/) const {
    Hit hit;
    if (!scene.intersect(ray, hit)) return glm::vec3(0.0f);
    if (view_ == DebugView::Normal) return guard(0.5f * hit.shading_normal + 0.5f);
    const Material& m = scene.material(hit);
    switch (m.kind) {
        case MaterialKind::Diffuse:
            return guard(scene.albedo(hit));
        case MaterialKind::Emissive:
            return guard(m.emission);
        default:
            return guard(m.albedo);
    }
}

}  // namespace librt
