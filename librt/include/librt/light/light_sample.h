#pragma once

#include <glm/vec3.hpp>

namespace librt {

/// What a light's sample_li returns: one direction from a reference point toward the
/// light, with the radiance arriving along it and its density.
struct LightLiSample {
    glm::vec3 wi{0.0f};  ///< unit direction from the reference point toward the light
    /// Radiance arriving at the reference point along -wi. For a delta light (a point), the
    /// factor that times cos(theta) gives the irradiance: I / d^2.
    glm::vec3 radiance{0.0f};
    float pdf = 0.0f;  ///< per unit solid angle at the reference point; 1 for a delta light
    /// Where a shadow ray toward the sample ends (spawn_ray_to takes end_slope times the
    /// origin's offset off it): the
    /// distance from the reference point to the emitting point along wi. Lights whose own
    /// surface the shadow ray skips give it exactly; triangle lights, which cannot skip
    /// theirs, shorten it by the rounding of their own test (see triangle_light.cpp).
    float distance = 0.0f;
    bool is_delta = false;  ///< a delta light: no BSDF-sampled direction can find it
    /// How much shorter the shadow ray must be per unit of its origin's offset off the
    /// receiving surface, so that the shifted segment still ends short of the light's own
    /// surface: 1 / |cos| at the emitter for lights whose surface the ray cannot skip
    /// (triangles), 0 for the others. spawn_ray_to (src/geometry/spawn_ray.h) applies it.
    float end_slope = 0.0f;

    /// True when there is a direction to use (pdf > 0).
    [[nodiscard]] bool valid() const { return pdf > 0.0f; }
};

/// What a light's sample_le returns: a ray leaving the light, for paths that start there
/// (light tracing, bidirectional path tracing). Its weight as a path's first throughput is
/// radiance |cos(normal, direction)| / (pdf_pos pdf_dir), and radiance / pdf_dir for a
/// light with a delta position (whose normal is 0).
struct LightLeSample {
    /// Where the ray starts: on the light, or for a light at infinity on a disk facing
    /// the scene.
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f};  ///< unit, the way the light travels
    /// Unit surface normal at origin on the side the ray leaves; 0 for a point or spot
    /// light; for a light at infinity, direction (the disk of the origin faces that way).
    glm::vec3 normal{0.0f};
    /// Emitted radiance Le(origin, direction) (area lights, lights at infinity; for a
    /// delta sun its irradiance, as pdf_dir is 1), or intensity I(direction) in W/sr for
    /// point and spot lights.
    glm::vec3 radiance{0.0f};
    /// Density of origin: per unit area on the light's surface, or on the disk a light at
    /// infinity starts its rays from; 1 for a delta position (point, spot).
    float pdf_pos = 0.0f;
    /// Density of direction per unit solid angle; 1 for a delta direction (a sun without
    /// angular radius).
    float pdf_dir = 0.0f;
    /// How far the ray must start off the surface (along normal) where that is more than
    /// ray_offset_scale(origin): a planar light is found again by a triangle test, which
    /// rounds at its corners' magnitude (ray_offset.h, barycentric_offset), so a light 1e5
    /// across next to the world origin gives ray_offset_scale of its corners. 0: none.
    float offset = 0.0f;
    bool delta_position = false;   ///< a point or spot light: no ray can hit the origin
    bool delta_direction = false;  ///< a sun without angular radius: one direction only

    /// True when there is a ray to use (both densities > 0).
    [[nodiscard]] bool valid() const { return pdf_pos > 0.0f && pdf_dir > 0.0f; }
};

/// The two densities with which sample_le would have drawn a given ray (see pdf_le).
struct LightLePdf {
    float pos = 0.0f;  ///< of the origin, as LightLeSample::pdf_pos
    float dir = 0.0f;  ///< of the direction, as LightLeSample::pdf_dir
};

/// The scene's bounds as a sphere, for lights at infinity: the points their rays start
/// from are drawn on a disk of this radius, perpendicular to the ray and tangent to the
/// sphere on the light's side (as pbrt 4th ed. 12.4 does), so every such ray that can meet
/// the scene is drawn with the same density 1 / (pi radius^2).
struct SceneSphere {
    glm::vec3 center{0.0f};  ///< centre of the scene's bounding box
    float radius = 0.0f;     ///< half its diagonal; a disk needs > 0
};

}  // namespace librt
