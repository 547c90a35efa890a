#pragma once

#include <librt/accel/bvh.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/geometry/sphere.h>
#include <librt/geometry/triangle.h>
#include <librt/render/light.h>
#include <librt/render/material.h>
#include <librt/render/texture.h>

#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace librt {

/// Relative part of the self-intersection offset: 2^-18, i.e. 32 to 64 float ulps of the
/// largest coordinate of the point.
inline constexpr float kRayOffsetRelative = 0x1p-18f;
/// Absolute floor of the self-intersection offset, for points near the origin.
inline constexpr float kRayOffsetAbsolute = 0x1p-20f;

/// Distance by which offset_ray_origin moves a point off its surface: an absolute floor
/// plus max(|p.x|, |p.y|, |p.z|) * 2^-18. A hit point computed in float lies within a few
/// ulps of its largest coordinate from the true surface (the ray parameter is rounded to
/// float, then o + t d rounds again), so 32+ ulps clears that error with a wide margin
/// while staying far below any feature of a sane scene: in the report's room (|p| ~ 100)
/// it is 4e-4, against the report's fixed 0.01; scaled by 1000 the scene gets 1000 times
/// the offset, which a fixed epsilon would not do. Geometry thinner than the offset (a
/// glass sheet of thickness ~1e-5 at that scale) can be stepped over.
[[nodiscard]] inline float ray_offset_scale(const glm::vec3& p) {
    const float m = std::max(std::max(std::fabs(p.x), std::fabs(p.y)), std::fabs(p.z));
    return kRayOffsetAbsolute + kRayOffsetRelative * m;
}

/// The origin of a ray leaving surface point `point` in `direction`: the point moved by
/// ray_offset_scale(point) along the unit geometric `normal`, to the side `direction`
/// goes (so a reflected ray starts above the surface and a refracted one below it).
[[nodiscard]] inline glm::vec3 offset_ray_origin(const glm::vec3& point, const glm::vec3& normal,
                                                 const glm::vec3& direction) {
    const float offset = ray_offset_scale(point);
    return glm::dot(normal, direction) >= 0.0f ? point + offset * normal : point - offset * normal;
}

/// A ray leaving a surface point in a unit direction, its origin offset off the surface.
[[nodiscard]] inline Ray spawn_ray(const glm::vec3& point, const glm::vec3& normal,
                                   const glm::vec3& direction) {
    Ray r;
    r.origin = offset_ray_origin(point, normal, direction);
    r.direction = direction;
    return r;
}

/// The geometry, materials, textures and lights of a render, with closest-hit and any-hit
/// queries over all of it.
///
/// Objects are spheres (tested analytically, in double precision, so the report's
/// radius-1000 walls stay exact) and triangle meshes (each with its own SAH TriangleBvh);
/// commit() builds a top-level SAH Bvh over the objects' boxes. Traversal dispatches on a
/// per-object tag, not a virtual call, and queries never allocate. Object ids count the
/// add_sphere / add_mesh / add_sphere_light calls from 0, the loose
/// triangles of add_triangle taking the id given at the first such call.
///
/// Normal conventions of Hit: geometric_normal is unit and points where the primitive
/// faces: outward for spheres, along (p1 - p0) x (p2 - p0) (counter-clockwise winding) for
/// triangles, whatever side the ray came from. shading_normal is the interpolated vertex
/// normal when the mesh has normals (flipped onto geometric_normal's side if it disagrees,
/// and replaced by it if degenerate), else equal to geometric_normal. Dielectric meshes
/// must therefore be closed and wound so that their normals point outward.
///
/// Any add_* after commit() un-commits the scene; queries then throw until commit() runs
/// again. A committed scene is immutable and may be queried from many threads at once.
class LIBRT_API Scene {
public:
    /// Adds a material (validated) and returns its id.
    std::uint32_t add_material(const Material& material);
    /// Adds a texture and returns its id, for Material::albedo_texture.
    std::int32_t add_texture(ImageTexture texture);

    /// Adds a sphere of the given material; returns its object id. Throws librt::Error
    /// for a non-finite centre, a radius not > 0, or an unknown material id.
    std::uint32_t add_sphere(const Sphere& sphere, std::uint32_t material);
    /// Adds a loose triangle; all loose triangles form one mesh object whose id is
    /// returned (the triangle's primitive id is its rank among loose triangles).
    std::uint32_t add_triangle(const Triangle& triangle, std::uint32_t material);
    /// Adds a mesh whose triangles all use `material` (its own materials are ignored);
    /// returns its object id. Throws librt::Error for an invalid mesh (librt::validate) or
    /// an unknown material id.
    std::uint32_t add_mesh(TriangleMesh mesh, std::uint32_t material);
    /// As add_mesh, with the builder of the mesh's BVH chosen (the report's median split
    /// for comparisons; SAH, the default, is faster to trace).
    std::uint32_t add_mesh(TriangleMesh mesh, std::uint32_t material, BvhBuilder builder);
    /// Adds a mesh whose triangle i uses scene material triangle_materials[i] (the mesh's
    /// own materials are ignored; io/obj_materials.h add_mesh_with_mtl maps them to scene
    /// materials and calls this); returns its object id. Throws librt::Error for an invalid
    /// mesh (librt::validate), a count of ids other than the triangle count, or an unknown
    /// material id.
    std::uint32_t add_mesh(TriangleMesh mesh, std::vector<std::uint32_t> triangle_materials,
                           BvhBuilder builder = BvhBuilder::Sah);
    /// Adds a point light (validated). Point lights are not geometry.
    void add_point_light(const PointLight& light);
    /// Adds a sphere light (validated) and the emissive sphere that is its surface;
    /// returns that sphere's object id.
    std::uint32_t add_sphere_light(const SphereLight& light);

    /// Builds the acceleration structures. Must be called after the last add_* and before
    /// any query; calling it again without changes does nothing.
    void commit();
    /// True when the scene is committed and queries may run.
    [[nodiscard]] bool committed() const { return committed_; }

    /// Closest hit with t in (ray.t_min, ray.t_max); fills `hit` (see the class comment)
    /// and returns true, or returns false and leaves `hit` alone. Throws librt::Error
    /// before commit().
    [[nodiscard]] bool intersect(const Ray& ray, Hit& hit) const;
    /// intersect() for renderers: the same hit, except that a sphere's uv (two inverse
    /// trigonometric calls) is computed only when its material has a texture, and is
    /// (0, 0) otherwise, since only texture lookups read it. What the integrators call.
    [[nodiscard]] bool intersect_for_shading(const Ray& ray, Hit& hit) const;
    /// True when anything lies in (ray.t_min, ray.t_max): for shadow rays. The object
    /// `ignored_object` (e.g. the sphere light being sampled) is skipped. Throws
    /// librt::Error before commit().
    [[nodiscard]] bool occluded(const Ray& ray, std::uint32_t ignored_object = kInvalidId) const;

    /// The material of a hit's primitive (per-triangle materials respected).
    [[nodiscard]] const Material& material(const Hit& hit) const {
        return materials_[material_id(hit)];
    }
    /// The scene material id of a hit's primitive.
    [[nodiscard]] std::uint32_t material_id(const Hit& hit) const;
    /// The diffuse reflectance at a hit: the material's texture looked up at hit.uv if it
    /// has one, else its albedo.
    [[nodiscard]] glm::vec3 albedo(const Hit& hit) const;

    /// Material by id.
    [[nodiscard]] const Material& material(std::uint32_t id) const { return materials_.at(id); }
    /// Number of materials.
    [[nodiscard]] std::size_t material_count() const { return materials_.size(); }
    /// Texture by id.
    [[nodiscard]] const ImageTexture& texture(std::int32_t id) const {
        return textures_.at(std::size_t(id));
    }
    /// Number of textures.
    [[nodiscard]] std::size_t texture_count() const { return textures_.size(); }
    /// Number of objects (spheres, meshes, the loose-triangle mesh, light spheres).
    [[nodiscard]] std::size_t object_count() const { return objects_.size(); }

    /// The point lights, in the order added.
    [[nodiscard]] std::span<const PointLight> point_lights() const { return point_lights_; }
    /// The sphere lights, in the order added.
    [[nodiscard]] std::span<const SphereLight> sphere_lights() const { return sphere_lights_; }
    /// Object id of sphere light i's surface.
    [[nodiscard]] std::uint32_t sphere_light_object(std::size_t i) const {
        return sphere_light_objects_.at(i);
    }
    /// True when the object is the surface of a sphere light, i.e. light sampling already
    /// accounts for its emission at diffuse surfaces.
    [[nodiscard]] bool is_sphere_light(std::uint32_t object_id) const {
        return object_id < objects_.size() && objects_[object_id].light;
    }

    /// True when some surface emits light that light sampling does not account for: an
    /// emissive material on anything but a sphere light's own sphere. When false, a path
    /// that has just scattered off a diffuse surface for the last time can find nothing
    /// more to add, so the integrator need not trace that last ray. Valid after commit().
    [[nodiscard]] bool has_unsampled_emitters() const { return unsampled_emitters_; }

    /// Bounding box of all objects (empty if none); valid after commit().
    [[nodiscard]] BBox bounds() const { return top_.bounds(); }

private:
    enum class ObjectKind : std::uint8_t { Sphere, Mesh };
    /// What the top-level traversal dispatches on.
    struct Object {
        ObjectKind kind;
        bool light = false;      ///< surface of a sphere light
        std::uint32_t index;     ///< into spheres_ or meshes_
        std::uint32_t material;  ///< uniform material, or kInvalidId for per-triangle ids
    };
    /// A sphere with the double-precision copies its test uses.
    struct SphereData {
        Sphere sphere;
        glm::dvec3 center;
        double radius2;
    };
    struct MeshData {
        TriangleMesh mesh;
        TriangleBvh bvh;
        std::vector<std::uint32_t> triangle_materials;  ///< scene ids, when per-triangle
        BvhBuilder builder = BvhBuilder::Sah;           ///< how commit() builds bvh
    };

    void require_committed() const;
    void check_material_id(std::uint32_t material) const;
    std::uint32_t add_object(ObjectKind kind, std::uint32_t index, std::uint32_t material);
    /// Calls test_object(object id, ray) -> bool for the objects the ray may hit, nearest
    /// box first, through flat_ or top_; stops at the first hit with AnyHit.
    template <bool AnyHit, class TestObject>
    bool visit_objects(Ray& ray, TestObject&& test_object) const;
    bool intersect_impl(const Ray& ray, Hit& hit, bool sphere_uv_always) const;
    void finish_hit(const Ray& ray, std::uint32_t object_id, const PrimitiveHit& prim,
                    bool sphere_uv_always, Hit& hit) const;

    std::vector<Material> materials_;
    std::vector<ImageTexture> textures_;
    std::vector<Object> objects_;
    std::vector<SphereData> spheres_;
    std::vector<MeshData> meshes_;
    std::uint32_t loose_object_ = kInvalidId;  ///< object of the add_triangle mesh
    std::vector<PointLight> point_lights_;
    std::vector<SphereLight> sphere_lights_;
    std::vector<std::uint32_t> sphere_light_objects_;

    /// Up to this many objects, the top level is a flat list of boxes rather than top_: the
    /// report's six radius-1000 wall spheres all overlap the room, so every interior node of
    /// a BVH over them does too and a ray visits nearly all of them, while the entry
    /// distances of a dozen boxes cost less than a walk down that tree (about 2x faster in
    /// the room).
    static constexpr std::uint32_t kFlatObjectLimit = 16;
    /// The objects' boxes as structure of arrays, when there are at most kFlatObjectLimit.
    struct FlatBoxes {
        std::array<float, kFlatObjectLimit> lo_x{}, lo_y{}, lo_z{}, hi_x{}, hi_y{}, hi_z{};
        std::array<std::uint32_t, kFlatObjectLimit> object{};  ///< box i -> object id
        std::uint32_t count = 0;                               ///< 0: use top_
    };

    Bvh top_;  ///< over objects_' boxes
    FlatBoxes flat_;
    std::vector<std::uint32_t> slot_object_;  ///< top_ slot -> object id
    bool unsampled_emitters_ = false;         ///< see has_unsampled_emitters()
    bool committed_ = false;
};

}  // namespace librt
