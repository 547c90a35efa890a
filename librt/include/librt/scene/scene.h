#pragma once

#include <librt/accel/bvh.h>
#include <librt/accel/top_level.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/geometry/ray_offset.h>
#include <librt/geometry/sphere.h>
#include <librt/geometry/triangle.h>
#include <librt/light/light.h>
#include <librt/light/light_sampler.h>
#include <librt/light/triangle_light.h>
#include <librt/material/material.h>
#include <librt/material/texture.h>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace librt {

/// Room for the material Scene::shade evaluates at a hit whose material varies per hit
/// (textures, a normal map, a one-sided back). It stays unconstructed until shade() fills
/// it, so a path loop can keep one per path at no cost for untextured scenes.
class ShadedMaterial {
public:
    ShadedMaterial() {}  // NOLINT: leaves the union member unconstructed on purpose

private:
    friend class Scene;
    union {
        Material material_;
    };
};

/// The geometry, materials, textures and lights of a render, with closest-hit and any-hit
/// queries over all of it.
///
/// The geometry lives in a TopLevel (accel/top_level.h): spheres (tested analytically, in
/// double precision, so the report's radius-1000 walls stay exact), triangle meshes (each
/// with its own SAH TriangleBvh) and instances of mesh prototypes (a prototype's triangles
/// and BVH stored once, placed by affine transforms; rays go to object space with the
/// direction not renormalised, so t is the world ray's); commit() builds it. The Scene adds
/// what the geometry does not know: materials, textures and lights. Traversal dispatches on
/// a per-object tag, not a virtual call, and queries never allocate. Object ids count the
/// add_sphere / add_mesh / add_instance / add_sphere_light calls from
/// 0, the loose triangles of add_triangle taking the id given at the first such call.
///
/// Normal conventions of Hit: geometric_normal is unit and points where the primitive
/// faces: outward for spheres, along (p1 - p0) x (p2 - p0) (counter-clockwise winding) for
/// triangles, whatever side the ray came from. shading_normal is the interpolated vertex
/// normal when the mesh has normals (flipped onto geometric_normal's side if it disagrees,
/// and replaced by it if degenerate), else equal to geometric_normal. Dielectric meshes
/// must therefore be closed and wound so that their normals point outward.
///
/// Materials with per-hit inputs (Material::varies_per_hit) are evaluated by shade(); a
/// material with an alpha test (Material::cuts_out) makes every query skip the hits where
/// its coverage is below the cut-off (the ray goes on past them), for those materials only.
/// A material with partial coverage (Material::alpha_blend) makes every query skip a hit
/// with probability 1 - coverage: stochastic opacity, whose expectation is the blend. The
/// decision is a hash of the ray (origin, direction) and the hit (object, primitive,
/// instance, t): the same for the same ray, whatever thread asks, and independent between
/// the rays of different samples as long as those differ (the renderer jitters every
/// camera ray) and between the surfaces along one ray.
///
/// One-sided materials (Material::double_sided false, glTF's default) are culled for camera
/// rays only: camera_passes() is true at their backs, and the integrators' camera rays (and
/// the joins of light paths to the lens) go on through them, as a rasterizer's back-face
/// culling hides them. Every other ray meets such a back as a black absorber, so a
/// single-sided wall still casts its shadow (the choice of Cycles' camera culling).
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
    /// Adds a sphere given in double (centre, radius): rays meet exactly this sphere, not
    /// its float rounding, so a wall of radius 1e5 stays where its author put it (normals
    /// and uv use the float sphere). Throws librt::Error as add_sphere(Sphere) does.
    std::uint32_t add_sphere(const glm::dvec3& center, double radius, std::uint32_t material);
    /// Adds a loose triangle; all loose triangles form one mesh object whose id is
    /// returned (the triangle's primitive id is its rank among loose triangles).
    std::uint32_t add_triangle(const Triangle& triangle, std::uint32_t material);
    /// Adds a mesh whose triangles all use `material` (its own materials are ignored);
    /// returns its object id. A mesh with uvs but no tangents whose material has a normal
    /// map or anisotropy gets tangents from its uvs (generate_tangents, v up). Throws
    /// librt::Error for an invalid mesh (librt::validate) or an unknown material id.
    std::uint32_t add_mesh(TriangleMesh mesh, std::uint32_t material);
    /// As add_mesh, with the builder of the mesh's BVH chosen (the report's median split
    /// for comparisons; SAH, the default, is faster to trace).
    std::uint32_t add_mesh(TriangleMesh mesh, std::uint32_t material, BvhBuilder builder);
    /// Adds a mesh whose triangle i uses scene material triangle_materials[i] (the mesh's
    /// own materials are ignored; obj/obj_materials.h add_mesh_with_mtl maps them to scene
    /// materials and calls this); returns its object id. Throws librt::Error for an invalid
    /// mesh (librt::validate), a count of ids other than the triangle count, or an unknown
    /// material id.
    std::uint32_t add_mesh(TriangleMesh mesh, std::vector<std::uint32_t> triangle_materials,
                           BvhBuilder builder = BvhBuilder::Sah);
    /// Adds a mesh prototype: its triangles and BVH (built by commit() with `builder`),
    /// stored once however many instances place it. A prototype alone is not geometry;
    /// returns the id add_instance takes. Throws librt::Error for an invalid mesh
    /// (librt::validate). The mesh's own materials are ignored.
    std::uint32_t add_mesh_prototype(TriangleMesh mesh, BvhBuilder builder = BvhBuilder::Sah);
    /// Places prototype `prototype` by the affine `object_to_world` matrix, all its triangles
    /// of `material`; returns its object id. Hits on it report the prototype's triangle as
    /// primitive_id and the instance's rank among add_instance calls as instance_id. Throws
    /// librt::Error for an unknown prototype or material id, or a matrix that is not finite,
    /// not affine (bottom row 0 0 0 1) or singular. A `material` with a normal map or
    /// anisotropy gives a prototype with uvs but no tangents tangents from its uvs
    /// (generate_tangents, v up), as add_mesh does.
    std::uint32_t add_instance(std::uint32_t prototype, const glm::mat4& object_to_world,
                               std::uint32_t material);
    /// Adds a point light (validated) to the light list. Point lights are not geometry.
    void add_point_light(const PointLight& light);
    /// Adds a sphere light (validated) to the light list, and the emissive sphere that is
    /// its surface; returns that sphere's object id. The sphere is an opaque emitter on
    /// both sides: a ray from inside sees its radiance too, and light sampling from inside
    /// samples its area (sample_sphere_direction), so MIS stays consistent there.
    std::uint32_t add_sphere_light(const SphereLight& light);
    /// Adds a quad light (validated) and the two emissive triangles that are its surface,
    /// wound to face along edge0 x edge1; returns that mesh's object id.
    std::uint32_t add_quad_light(const QuadLight& light);
    /// Adds a disk light (validated) and the emissive triangle fan (kDiskLightSides
    /// triangles) that is its surface; returns that mesh's object id.
    std::uint32_t add_disk_light(const DiskLight& light);
    /// Adds a spot light (validated); not geometry. Returns its index in lights().
    std::uint32_t add_spot_light(const SpotLight& light);
    /// Adds a directional (sun) light (validated); returns its index in lights().
    std::uint32_t add_directional_light(const DirectionalLight& light);
    /// Adds an environment light (validated): what rays leaving the scene see; when
    /// camera_visible is false, camera rays that leave see black. Returns its index.
    std::uint32_t add_environment_light(const EnvironmentLight& light, bool camera_visible = true);
    /// Hides object `object_id` from camera rays (or shows it again): they pass through it
    /// as if it were not there, while every other ray still hits it (an emitter keeps
    /// lighting the scene). Throws librt::Error for an unknown object id.
    void set_camera_visible(std::uint32_t object_id, bool visible);
    /// False when camera rays pass through object `object_id`.
    [[nodiscard]] bool camera_visible(std::uint32_t object_id) const {
        return object_id >= objects_.size() || objects_[object_id].camera_visible;
    }
    /// False when no object was ever hidden from the camera: camera_visible() is then true
    /// for every id, and the path loop skips that lookup at each camera hit.
    [[nodiscard]] bool may_hide_objects() const { return hidden_objects_; }
    /// False when camera_passes() is false at every hit: no object hidden from the camera
    /// and no one-sided material. The path loop asks this first at each camera hit.
    [[nodiscard]] bool camera_may_pass() const { return hidden_objects_ || one_sided_; }
    /// True when a camera ray along `direction` goes on through `hit`: an object hidden
    /// from the camera (set_camera_visible), or the back of a one-sided material (not
    /// double_sided; direction not against the geometric normal): back-face culling.
    [[nodiscard]] bool camera_passes(const Hit& hit, const glm::vec3& direction) const;
    /// True when some material is one-sided (Material::double_sided false).
    [[nodiscard]] bool has_one_sided_surfaces() const { return one_sided_; }

    /// Which emissive triangles commit() makes lights of (see TriangleLightSettings; by
    /// default the negligible ones are left to BSDF sampling). Un-commits the scene. Throws
    /// librt::Error for a negligible_power outside [0, 1] (or NaN).
    void set_triangle_light_settings(const TriangleLightSettings& settings);
    /// What set_triangle_light_settings set (the defaults until then).
    [[nodiscard]] const TriangleLightSettings& triangle_light_settings() const {
        return triangle_light_settings_;
    }

    /// Builds the acceleration structures: after the last add_*, before any query; again
    /// without changes, nothing. Out of memory: librt::Error, the scene left uncommitted.
    void commit();
    /// True when the scene is committed and queries may run.
    [[nodiscard]] bool committed() const { return committed_; }

    /// Closest hit with t in (ray.t_min, ray.t_max); fills `hit` (see the class comment)
    /// and returns true, or returns false and leaves `hit` alone. Where a pane (a material
    /// that may pass light through) lies in another object's surface, that surface is the
    /// hit. Throws librt::Error before commit().
    [[nodiscard]] bool intersect(const Ray& ray, Hit& hit) const {
        require_committed();
        if (careful_queries_) [[unlikely]]
            return intersect_carefully(ray, hit, true);
        return top_.intersect(ray, hit, true);
    }
    /// intersect(ray, Hit&)'s closest hit without the surface record: t, ids and the unit
    /// geometric normal, bit for bit the finished hit's (TopLevel::intersect(ray,
    /// GeometricHit&): the triangle from its BVH leaf, the mesh not read). In a scene with
    /// cut-outs or panes it goes through the finished query (their tests need the surface).
    /// Fills `hit` and returns true, or returns false and leaves `hit` alone. Throws
    /// librt::Error before commit().
    [[nodiscard]] bool intersect(const Ray& ray, GeometricHit& hit) const {
        require_committed();
        if (careful_queries_) [[unlikely]]
            return intersect_geometric_carefully(ray, hit);
        return top_.intersect(ray, hit);
    }
    /// intersect() for renderers: the same hit, except that a sphere's uv (two inverse
    /// trigonometric calls) is computed only when its material has a texture, and is
    /// (0, 0) otherwise, since only texture lookups read it (in a scene with an alpha
    /// test, always). What the integrators call.
    [[nodiscard]] bool intersect_for_shading(const Ray& ray, Hit& hit) const {
        require_committed();
        if (careful_queries_) [[unlikely]]
            return intersect_carefully(ray, hit, false);
        return top_.intersect(ray, hit, false);
    }
    /// True when anything lies in (ray.t_min, ray.t_max): for shadow rays. The object
    /// `ignored_object` (e.g. the sphere light being sampled) is skipped. Throws
    /// librt::Error before commit().
    // Forced inline: the path loop's shadow ray, which g++ kept out of line there
    // (docs/benchmarks.md, "Code shaped by measurement").
    [[nodiscard, gnu::always_inline]] bool occluded(
        const Ray& ray, std::uint32_t ignored_object = kInvalidId) const {
        require_committed();
        if (!top_.occluded(ray, ignored_object)) return false;
        // Something is there; with cut-outs in the scene it may be a hole only.
        if (cut_outs_) [[unlikely]]
            return occluded_past_cut_outs(ray, ignored_object);
        return true;
    }

    /// The material of a hit's primitive (per-triangle materials respected).
    [[nodiscard]] const Material& material(const Hit& hit) const {
        return materials_[material_id(hit)];
    }
    /// The material at a hit with its per-hit inputs evaluated: the stored material itself
    /// when it has none (Material::varies_per_hit false: no cost), else `scratch` filled
    /// with it, its textures looked up at hit.uv (base colour, metallic-roughness,
    /// emission), the mesh's vertex colour multiplied in (base colour, else albedo), and
    /// hit.shading_normal bent by its normal map (then adapted to `direction` by
    /// adapt_shading_normal, so that its mirror direction stays above the surface), and an
    /// anisotropic material's
    /// anisotropy_direction set from the surface's tangent frame (a mesh's tangents, which
    /// add_mesh generates from uvs for such a material, or a sphere's dP/du), turned by
    /// anisotropy_rotation and its texture. A one-sided material seen
    /// from its back (`direction`, the ray's, against the geometric normal) gives a black
    /// material: no scattering, no emission. The returned reference lives as long as the
    /// scene and `scratch`.
    [[nodiscard]] const Material& shade(Hit& hit, const glm::vec3& direction,
                                        ShadedMaterial& scratch) const {
        // Inline and one load for the common object (a uniform, plain material): cheaper
        // than material(hit)'s call; per-triangle and textured materials go out of line.
        const std::uint32_t plain = objects_[hit.object_id].plain_material;
        if (plain != kInvalidId) [[likely]]
            return materials_[plain];
        return shade_varying(hit, direction, scratch);
    }
    /// The coverage at a hit: the material's alpha times its base colour texture's alpha
    /// at hit.uv and the vertex colour's alpha (1 without any of them).
    [[nodiscard]] float coverage(const Hit& hit) const;
    /// The ambient occlusion factor of the hit's material at a hit (Material::
    /// occlusion_texture): 1 + occlusion_strength (R - 1) in every channel, 1 without one.
    /// For the albedo AOV only; shading never reads it.
    [[nodiscard]] glm::vec3 occlusion(const Hit& hit) const;
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
    /// Number of objects (spheres, meshes, the loose-triangle mesh, instances, light spheres).
    [[nodiscard]] std::size_t object_count() const { return objects_.size(); }
    /// Number of instances (add_instance calls).
    [[nodiscard]] std::size_t instance_count() const { return top_.instance_count(); }
    /// Object id of instance i (Hit::instance_id == i).
    [[nodiscard]] std::uint32_t instance_object(std::size_t i) const {
        return top_.instance_object(std::uint32_t(i));
    }
    /// The geometry: objects, prototypes and the structure over them; built by commit().
    [[nodiscard]] const TopLevel& top_level() const { return top_; }

    /// Every light: those added, in the order added, then (after commit()) one
    /// TriangleLight per emissive triangle of the mesh and instance objects, object by
    /// object (an instance's triangles mapped to the world by its matrix; one-sided when
    /// the material is not double_sided, textured by its emission texture; cut-out
    /// emitters, triangles black over their texture footprint and those of negligible
    /// power, TriangleLightSettings, are left to BSDF sampling).
    [[nodiscard]] std::span<const Light> lights() const { return lights_; }
    /// Chooses the light a shading point samples; valid after commit().
    [[nodiscard]] const LightSampler& light_sampler() const { return light_sampler_; }
    /// Index in lights() of the light whose surface is object `object_id`, or kInvalidId
    /// when the object is no light's surface (its emission, if any, is not light-sampled).
    [[nodiscard]] std::uint32_t light_of_object(std::uint32_t object_id) const {
        return object_id < light_of_object_.size() ? light_of_object_[object_id] : kInvalidId;
    }
    /// Index in lights() of the light whose surface a hit is on: the object's light, else
    /// the TriangleLight of the hit triangle of an emissive mesh (valid after commit()),
    /// else kInvalidId.
    [[nodiscard]] std::uint32_t light_of_hit(const Hit& hit) const {
        const std::uint32_t l = light_of_object(hit.object_id);
        if (l != kInvalidId || hit.object_id >= triangle_light_base_.size()) return l;
        const std::uint32_t base = triangle_light_base_[hit.object_id];
        return base == kInvalidId ? kInvalidId : triangle_light_[base + hit.primitive_id];
    }
    /// Indices in lights() of the lights at infinity (see is_infinite), after commit().
    [[nodiscard]] std::span<const std::uint32_t> infinite_lights() const {
        return infinite_lights_;
    }

    /// True when some surface emits light that light sampling does not account for: an
    /// emissive material on anything but a light's own surface. When false, a path that
    /// has just scattered off a diffuse surface for the last time can find nothing more to
    /// add, so the integrator need not trace that last ray. Valid after commit().
    [[nodiscard]] bool has_unsampled_emitters() const { return unsampled_emitters_; }

    /// True when some material may pass light straight through (a Null lobe: bsdf.h's
    /// may_pass_through), so a shadow ray must look through such surfaces instead of
    /// stopping at the first hit. When false, occlusion is one any-hit query. After commit().
    [[nodiscard]] bool has_pass_through_surfaces() const { return pass_through_surfaces_; }

    /// Bounding box of all objects (empty if none); valid after commit().
    [[nodiscard]] BBox bounds() const { return top_.bounds(); }
    /// The sphere around bounds(): its centre, and half its diagonal as radius (centre 0
    /// and radius 1 when empty), the size lights at infinity are given (their power, the
    /// disk their sample_le starts rays from); valid after commit().
    [[nodiscard]] SceneSphere bounding_sphere() const;

private:
    /// What the scene adds to a geometric object of top_ (same id).
    struct Object {
        std::uint32_t index;     ///< into triangle_materials_ when material is kInvalidId
        std::uint32_t material;  ///< uniform material, or kInvalidId for per-triangle ids
        /// `material` when it is uniform and has no per-hit inputs (shade()'s one-load path),
        /// else kInvalidId.
        std::uint32_t plain_material;
        bool camera_visible = true;  ///< see set_camera_visible
    };

    /// Inline, since every query starts with it; the throw is out of line.
    void require_committed() const {
        if (!committed_) throw_not_committed();
    }
    [[noreturn]] static void throw_not_committed();
    void check_material_id(std::uint32_t material) const;
    std::uint32_t add_object(std::uint32_t top_id, std::uint32_t material);
    std::uint32_t add_mesh_object(TriangleMesh mesh, BvhBuilder builder, std::uint32_t material,
                                  std::vector<std::uint32_t> per_triangle);
    std::uint32_t add_light(Light light);
    std::uint32_t add_surface_light(Light light, TriangleMesh surface, const glm::vec3& radiance);
    void make_triangle_lights();
    /// Appends to lights_ the candidate triangle lights TriangleLightSettings keeps, moving
    /// them out of `candidates`, and maps triangle_light_ from candidate to light indices.
    void keep_triangle_lights(std::vector<Light>& candidates);
    /// Lets every light learn what it needs of the scene (preprocess in light/light.h:
    /// the scene's size, the opaque analytic spheres that may bury a sphere light) and
    /// lists the lights at infinity.
    void preprocess_lights();
    void check_texture_ids(const Material& material) const;
    const Material& shade_varying(Hit& hit, const glm::vec3& direction,
                                  ShadedMaterial& scratch) const;
    /// Sets m.anisotropy_direction (and scales m.anisotropy by its texture) at a hit.
    void anisotropy_at(const Hit& hit, Material& m) const;
    /// The uv a texture slot reads at a hit: hit.uv, or the mesh's second set (uv_set 1).
    [[nodiscard]] glm::vec2 slot_uv(const TextureSlot& slot, const Hit& hit) const;
    /// The closest hit in a scene with cut-outs or panes: past the holes of alpha-tested
    /// surfaces, and, where a pane (a material that may pass light through) lies in the
    /// plane of another surface, that surface instead of the pane (surface_under_pane).
    bool intersect_carefully(const Ray& ray, Hit& hit, bool every_sphere_uv) const;
    /// intersect_carefully(ray, hit, true) as a GeometricHit.
    bool intersect_geometric_carefully(const Ray& ray, GeometricHit& hit) const;
    /// Replaces `pane` (the closest hit of `ray`, on a material that may pass light
    /// through) by the closest surface of another object within a relative 1e-5 of its t,
    /// when there is one.
    void surface_under_pane(const Ray& ray, Hit& pane) const;
    /// True when `hit` of `ray` falls in a hole of an alpha-tested surface (coverage below
    /// its material's alpha_cutoff) or, on a partly covered one (alpha_blend), the ray's
    /// hash says it passes (probability 1 - coverage): rays pass there as if nothing were hit.
    [[nodiscard]] bool in_cut_out_hole(const Ray& ray, const Hit& hit) const;
    bool intersect_past_cut_outs(const Ray& ray, Hit& hit) const;
    bool occluded_past_cut_outs(const Ray& ray, std::uint32_t ignored_object) const;

    std::vector<Material> materials_;
    std::vector<ImageTexture> textures_;
    std::vector<Object> objects_;
    std::vector<std::vector<std::uint32_t>> triangle_materials_;  ///< scene ids, per triangle
    std::uint32_t loose_object_ = kInvalidId;  ///< object of the add_triangle mesh
    std::vector<Light> lights_;
    std::size_t added_lights_ = 0;  ///< lights_[0, added_lights_) were added; the rest commit()'s
    std::vector<std::uint32_t> light_of_object_;  ///< object id -> light index (kInvalidId)
    /// Object id -> start in triangle_light_ of its triangles' light indices (kInvalidId).
    std::vector<std::uint32_t> triangle_light_base_;
    std::vector<std::uint32_t> triangle_light_;      ///< per triangle: light index or kInvalidId
    std::vector<std::uint32_t> infinite_lights_;     ///< see infinite_lights()
    LightSampler light_sampler_;                     ///< over lights_, built by commit()
    TriangleLightSettings triangle_light_settings_;  ///< see set_triangle_light_settings

    TopLevel top_;                        ///< the geometry and its acceleration structure
    bool unsampled_emitters_ = false;     ///< see has_unsampled_emitters()
    bool pass_through_surfaces_ = false;  ///< see has_pass_through_surfaces()
    bool cut_outs_ = false;               ///< some material cuts_out()
    bool careful_queries_ = false;        ///< cut_outs_ or pass_through_surfaces_
    bool hidden_objects_ = false;         ///< see may_hide_objects()
    bool one_sided_ = false;              ///< see has_one_sided_surfaces()
    bool committed_ = false;
};

}  // namespace librt
