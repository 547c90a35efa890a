#include "render/aov.h"

#include <librt/render/scatter.h>
#include <librt/render/scene.h>
#include <librt/sampling/rng.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {

namespace {

/// Mixed into the seed so the AOV stream of a sample differs from its integrator stream.
constexpr std::uint64_t kAovStream = 0x41f0'5eed'a0c5'1a7eULL;

}  // namespace

AovSample sample_aovs(const Scene& scene, const Ray& camera_ray, std::uint32_t x, std::uint32_t y,
                      std::uint32_t sample, std::uint64_t seed) {
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
    for (int bounce = 0; bounce <= kAovMaxSpecularBounces; ++bounce) {
        Hit hit;
        if (!scene.intersect_for_shading(ray, hit)) return out;  // escaped: albedo 0
        if (bounce == 0) {
            out.hit = true;
            out.depth = hit.t;
        }
        const Material& m = scene.material(hit);
        if (!m.is_specular()) {
            // Emitters reflect nothing; every other surface reflects its (textured) albedo.
            out.albedo =
                m.kind == MaterialKind::Emissive ? glm::vec3(0.0f) : tint * scene.albedo(hit);
            out.normal = hit.shading_normal;
            return out;
        }
        // Through a mirror or glass, as the path tracer goes: about the shading normal,
        // falling back to the geometric one when the shading normal is too bent.
        const glm::vec3& d = ray.direction;
        const bool front = glm::dot(d, hit.geometric_normal) < 0.0f;
        const glm::vec3 ng = front ? hit.geometric_normal : -hit.geometric_normal;
        glm::vec3 wi;
        if (m.kind == MaterialKind::Mirror) {
            wi = reflect(d, front ? hit.shading_normal : -hit.shading_normal);
            if (glm::dot(wi, ng) <= 0.0f) wi = reflect(d, ng);
        } else {
            const float u = m.fresnel ? rng.next_float() : 0.0f;
            DielectricScatter sc = scatter_dielectric(d, hit.shading_normal, m.ior, m.fresnel, u);
            if (sc.transmitted == (glm::dot(sc.direction, ng) > 0.0f))
                sc = scatter_dielectric(d, hit.geometric_normal, m.ior, m.fresnel, u);
            wi = sc.direction;
        }
        tint *= m.albedo;
        ray = spawn_ray(hit.point, hit.geometric_normal, wi);
    }
    return out;  // too many specular bounces: albedo 0
}

}  // namespace librt
