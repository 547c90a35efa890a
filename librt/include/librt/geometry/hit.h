#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>

namespace librt {

/// Sentinel for "no primitive / no object".
inline constexpr std::uint32_t kInvalidId = std::numeric_limits<std::uint32_t>::max();

/// What traversal knows about a hit: cheap to produce, enough to finish later.
struct PrimitiveHit {
    float t = std::numeric_limits<float>::infinity();  ///< ray parameter of the hit; inf if none
    float u = 0.0f;  ///< barycentric weight of vertex 1 (triangles) or unused
    float v = 0.0f;  ///< barycentric weight of vertex 2 (triangles) or unused
    std::uint32_t primitive_id = kInvalidId;  ///< the primitive hit; kInvalidId for a miss
    /// True when something was hit.
    [[nodiscard]] bool valid() const { return primitive_id != kInvalidId; }
};

/// The full surface record a shader needs, filled in once for the nearest hit.
struct Hit {
    float t = std::numeric_limits<float>::infinity();  ///< ray parameter of the hit; inf if none
    glm::vec3 point{0.0f};                             ///< the surface point hit, in world space
    glm::vec3 geometric_normal{0.0f};                  ///< unit, from the primitive's shape
    glm::vec3 shading_normal{0.0f};  ///< unit, interpolated when the mesh has normals
    glm::vec2 uv{0.0f};              ///< surface parameterisation or texture coordinates
    /// How far a ray leaving `point` starts off the surface, along geometric_normal
    /// (offset_ray_origin): a bound on the point's rounding and on that of the next ray's
    /// test against the same primitive (ray_offset.h). At least ray_offset_scale(point).
    float offset = 0.0f;
    std::uint32_t primitive_id = kInvalidId;  ///< triangle index within its mesh (an
                                              ///< instance's: its prototype's), or 0
    std::uint32_t object_id = kInvalidId;     ///< index of the object in its scene
    /// Rank of the instance hit among its scene's add_instance calls; kInvalidId when the
    /// object is not an instance.
    std::uint32_t instance_id = kInvalidId;
};

/// What a closest-hit query knows without finishing the surface record (as Embree's
/// rtcIntersect1 returns Ng, primID, geomID, instID): t, the ids and the geometric normal,
/// taken from the BVH leaf's own copy of the triangle, so the mesh's index and vertex arrays
/// are not read. Every field equals the finished Hit's of the same query bit for bit.
struct GeometricHit {
    float t = std::numeric_limits<float>::infinity();  ///< ray parameter of the hit; inf if none
    /// Unit, world space: Hit::geometric_normal (the winding's for triangles, by the inverse
    /// transpose for instances, outward for spheres).
    glm::vec3 geometric_normal{0.0f};
    std::uint32_t primitive_id = kInvalidId;  ///< as Hit::primitive_id
    std::uint32_t object_id = kInvalidId;     ///< as Hit::object_id
    std::uint32_t instance_id = kInvalidId;   ///< as Hit::instance_id
};

}  // namespace librt
