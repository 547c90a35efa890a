#include "integrator/transmittance.h"

#include "material/bsdf_dispatch.h"

#include <librt/geometry/ray_offset.h>
#include <librt/material/bsdf.h>

#include <algorithm>

namespace librt {

namespace {

// transmittance(); to_lens: the segment is a join to the lens, which crosses what camera
// rays cross (Scene::camera_passes, the camera looking back along it).
glm::vec3 segment_through(const Scene& scene, Ray ray, std::uint32_t ignored_object, bool to_lens) {
    glm::vec3 through(1.0f);
    if (!(ray.t_max > 0.0f)) return through;
    ShadedMaterial shaded;
    for (int crossed = 0; crossed <= kMaxShadowCrossings; ++crossed) {
        Hit hit;
        if (!scene.intersect_for_shading(ray, hit)) return through;
        if (hit.object_id != ignored_object &&
            !(to_lens && scene.camera_passes(hit, -ray.direction))) {
            const Material& m = scene.shade(hit, ray.direction, shaded);
            if (!has(bsdfs::lobes_of(m), BsdfLobe::Null)) return glm::vec3(0.0f);
            const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
            const ShadingPoint point{
                ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction), albedo};
            through *= bsdfs::pass_through_of(m, point, point.frame.to_local(-ray.direction));
            if (!(std::max(std::max(through.x, through.y), through.z) > 0.0f))
                return glm::vec3(0.0f);
        }
        // On along the rest of the segment, from just past the surface.
        const float rest = ray.t_max - hit.t;
        if (!(rest > 0.0f)) return through;
        ray.origin = offset_ray_origin(hit.point, hit.geometric_normal, hit.offset, ray.direction);
        ray.t_min = 0.0f;
        ray.t_max = rest;
    }
    return glm::vec3(0.0f);
}

}  // namespace

glm::vec3 transmittance(const Scene& scene, Ray ray, std::uint32_t ignored_object) {
    return segment_through(scene, ray, ignored_object, false);
}

glm::vec3 lens_transmittance(const Scene& scene, const Ray& ray) {
    if (!scene.camera_may_pass()) return shadow_transmittance(scene, ray);
    // Most joins are clear: one any-hit query says so (glTF's one-sided default must not
    // turn every join into a walk of closest hits).
    if (!scene.has_pass_through_surfaces() && unoccluded(scene, ray)) return glm::vec3(1.0f);
    return segment_through(scene, ray, kInvalidId, true);
}

Crossing cross_null(const Scene& scene, const Material& m, const Hit& hit,
                    const glm::vec3& direction, Sampler& sampler, std::uint32_t decision) {
    const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
    const ShadingPoint point{ShadingFrame::at(hit.shading_normal, hit.geometric_normal, direction),
                             albedo};
    const glm::vec3 through = bsdfs::pass_through_of(m, point, point.frame.to_local(-direction));
    const float p = std::clamp((through.x + through.y + through.z) / 3.0f, 0.0f, 1.0f);
    sampler.set_dimension(SampleDimensions::kPassThrough + decision);
    if (sampler.next_1d() < p) return {true, through / p};
    return {false, glm::vec3(1.0f / (1.0f - p))};
}

}  // namespace librt
