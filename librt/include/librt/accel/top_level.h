#pragma once

#include <librt/accel/bvh.h>
#include <librt/accel/bvh_builder.h>
#include <librt/accel/simd.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/geometry/sphere.h>
#include <librt/geometry/triangle.h>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace librt {

namespace detail {
struct SphereLanes;  // src/accel/sphere_roots.h
}  // namespace detail

/// What a top-level object is.
enum class ObjectKind : std::uint8_t {
    Sphere,    ///< an analytic sphere, tested in double precision
    Mesh,      ///< a mesh prototype in world space as it is (no transform)
    Instance,  ///< a mesh prototype placed by an affine transform
};

/// What the top level knows of a closest hit: the object and the primitive hit in it (for
/// meshes and instances the prototype's triangle index and barycentrics; t is the world
/// ray's own parameter, whatever the object).
struct ObjectHit {
    std::uint32_t object_id = kInvalidId;  ///< the object hit, kInvalidId for a miss
    PrimitiveHit primitive;                ///< the hit within it
};

/// The top level of a scene: its geometric objects (analytic spheres, triangle meshes and
/// instances of mesh prototypes) over one acceleration structure, with closest-hit and
/// any-hit queries and the finishing of a hit into a surface record. It knows nothing of
/// materials or lights.
///
/// A prototype is a mesh with its TriangleBvh, built once by build(); a mesh object shows
/// it as it is, an instance places it by an affine object-to-world matrix M. However many
/// objects use a prototype, its triangles and BVH are stored once; an instance costs a few
/// matrices.
///
/// Instances: a world ray (o, d) is taken to object space as (M^-1 o, M^-1 d), the
/// direction NOT renormalised, so a hit's t is the same in both spaces and t_min / t_max
/// carry over unchanged. The hit comes back with its point by M, its normals by the
/// inverse transpose of M's linear part, renormalised; under a mirroring M (negative
/// determinant) the geometric normal is therefore the inverse transpose of the prototype's
/// winding normal, i.e. what transform() gives a baked copy (which swaps two corners).
/// Instance boxes are the prototype box's eight corners mapped by M, padded by 2^-18 of
/// their largest coordinate, so rounding of the ray transform never loses a hit.
///
/// Up to kFlatObjectLimit objects, the top level is a flat list of boxes tested four at a
/// time; beyond that a SAH Bvh over the objects' boxes (see kFlatObjectLimit). A flat list
/// of spheres only (smallpt's room) skips the boxes: every sphere's double-precision root
/// is computed at once, up to eight spheres per instruction (AVX-512; four with AVX, two
/// with SSE2), the same roots
/// bit for bit as the one-at-a-time test, and the nearest is the hit; when two roots lie
/// within a few float steps of each other the boxes are visited as otherwise, so the hit
/// is always the one the box order gives. (With a mesh in the list the boxes are always
/// visited: there the early exits of the one-at-a-time test cost fewer instructions and
/// less time than computing every root; the synthesis, docs/benchmarks.md.) A query
/// through occluded() visits a flat list's boxes in the order the objects were added,
/// without `ignored_object`'s box: any hit ends it, so no nearest-first order is needed.
///
/// Object ids count add_sphere / add_mesh / add_instance calls from 0; prototype ids count
/// add_prototype calls. Any add_* after build() un-builds; queries
/// then throw until build() runs again. A built TopLevel is immutable and may be queried
/// from many threads at once.
class LIBRT_API TopLevel {
public:
    /// Up to this many objects, the top level is a flat list of boxes rather than a Bvh: the
    /// report's six radius-1000 wall spheres all overlap the room, so every interior node of
    /// a BVH over them does too and a ray visits nearly all of them, while the entry
    /// distances of a dozen boxes cost less than a walk down that tree (about 2x faster in
    /// the room).
    static constexpr std::uint32_t kFlatObjectLimit = 16;

    /// Adds a sphere; returns its object id. `uv`: whether intersect(ray, hit, false)
    /// computes the sphere's uv (two inverse trigonometric calls) or leaves it (0, 0).
    /// Throws librt::Error for a non-finite centre or a radius not > 0.
    std::uint32_t add_sphere(const Sphere& sphere, bool uv = true);
    /// Adds a sphere given in double: its intersection test uses exactly these values,
    /// its normal and uv the float-rounded sphere. Throws as add_sphere(Sphere).
    std::uint32_t add_sphere(const glm::dvec3& center, double radius, bool uv = true);
    /// Adds a mesh prototype (its BVH built by build(), with `builder`); returns its
    /// prototype id. A prototype alone is not geometry: add_mesh or add_instance shows it.
    /// Throws librt::Error for an invalid mesh (librt::validate).
    std::uint32_t add_prototype(TriangleMesh mesh, BvhBuilder builder = BvhBuilder::Sah);
    /// Gives prototype `prototype` the tangents generate_tangents(mesh, v_down) makes from
    /// its uvs when it has uvs, not all equal, and no tangents (else nothing): for a
    /// material that needs a tangent frame placed on a prototype added without one. Throws
    /// librt::Error for an unknown prototype.
    void generate_prototype_tangents(std::uint32_t prototype, bool v_down);
    /// Adds a loose triangle; all loose triangles form one mesh object, created at the
    /// first call, whose id is returned (the triangle's primitive id is its rank among
    /// loose triangles). Throws librt::Error, adding nothing, for a non-finite corner.
    std::uint32_t add_triangle(const Triangle& triangle);
    /// Shows a prototype as it is, in world space; returns the object id. Throws
    /// librt::Error for an unknown prototype.
    std::uint32_t add_mesh(std::uint32_t prototype);
    /// Places a prototype by an affine object-to-world matrix; returns the object id (its
    /// instance id is its rank among add_instance calls). Throws librt::Error for an unknown
    /// prototype or a matrix that is not finite, not affine (bottom row 0 0 0 1) or singular.
    std::uint32_t add_instance(std::uint32_t prototype, const glm::mat4& object_to_world);

    /// Builds the prototypes' BVHs not yet built and the structure over the objects; calling
    /// it again without changes does nothing.
    void build();
    /// True when built and queries may run.
    [[nodiscard]] bool built() const { return query_ != Query::None; }

    /// The instruction set of the sphere tests of a flat list of spheres only (see the class
    /// comment): default_simd_path() at first; Sse tests two spheres per instruction, Avx2
    /// four (AVX), Avx512 eight, Scalar one sphere at a time as each box is visited. Every path
    /// gives the same hits. Not thread-safe against queries running at the same time; throws
    /// librt::Error when simd_path_supported(path) is false.
    void set_simd_path(SimdPath path);
    /// The instruction set the sphere tests use (see set_simd_path).
    [[nodiscard]] SimdPath simd_path() const { return simd_path_; }

    /// Closest hit with t in (ray.t_min, ray.t_max): fills `hit` and returns true, or
    /// returns false and leaves `hit` alone. Throws librt::Error before build().
    [[nodiscard]] bool intersect(const Ray& ray, ObjectHit& hit) const;
    /// Closest hit with t in (ray.t_min, ray.t_max), finished (see finish()), a sphere's uv
    /// computed when `every_sphere_uv` is true or the sphere was added with uv = true; or
    /// false, `hit` left alone. Throws librt::Error before build().
    [[nodiscard]] bool intersect(const Ray& ray, Hit& hit, bool every_sphere_uv = true) const;
    /// The closest hit of intersect(ray, Hit&) without its surface record: t, ids and the
    /// unit geometric normal, each bit for bit the finished hit's, the triangle's normal
    /// from its BVH leaf (TriangleBvh::intersect(ray, normal)) instead of the mesh (for
    /// incoherent rays, a cache miss or more a hit saved). Fills `hit` and returns true, or
    /// returns false and leaves `hit` alone. Throws librt::Error before build().
    [[nodiscard]] bool intersect(const Ray& ray, GeometricHit& hit) const;
    /// intersect(ray, hit, every_sphere_uv) over every object but `ignored_object` (the
    /// surface a pane lies on, found past the pane itself). Throws librt::Error before build().
    [[nodiscard]] bool intersect_ignoring(const Ray& ray, Hit& hit, std::uint32_t ignored_object,
                                          bool every_sphere_uv = true) const;
    /// True when anything but object `ignored_object` lies in (ray.t_min, ray.t_max).
    /// Throws librt::Error before build().
    [[nodiscard]] bool occluded(const Ray& ray, std::uint32_t ignored_object = kInvalidId) const;
    /// The surface record of a hit intersect() returned for `ray`: t, world point, unit
    /// geometric normal (outward for spheres, the winding's for triangles, mapped by the
    /// inverse transpose for instances), shading normal (interpolated vertex normals when
    /// the mesh has them, flipped onto the geometric normal's side, else the geometric
    /// normal), uv (a mesh's uvs, else the barycentrics (b1, b2); a sphere's, v growing
    /// toward +y, when `every_sphere_uv` is true or the sphere was added with uv = true,
    /// else (0, 0)), primitive, object and instance ids.
    void finish(const Ray& ray, const ObjectHit& hit, bool every_sphere_uv, Hit& out) const;

    /// The barycentric coordinates (b1, b2) of a finished hit's point on its triangle
    /// (prototype space for an instance), recomputed from the point, for attributes
    /// finish() does not interpolate; (0, 0) for a sphere.
    [[nodiscard]] glm::vec2 barycentrics(const Hit& hit) const;
    /// The tangent at a finished hit on a mesh or instance whose prototype has tangents,
    /// interpolated, in world space: xyz by the object-to-world matrix (unnormalised), w
    /// the bitangent sign (negated by a mirroring instance). (0, 0, 0, 0) otherwise.
    [[nodiscard]] glm::vec4 tangent(const Hit& hit) const;
    /// True when object `id` is a mesh or instance whose prototype has vertex colors.
    [[nodiscard]] bool has_colors(std::uint32_t id) const;
    /// The vertex color interpolated at a finished hit on a mesh or instance whose
    /// prototype has colors; (1, 1, 1, 1) otherwise.
    [[nodiscard]] glm::vec4 color(const Hit& hit) const;
    /// The second uv set (TriangleMesh::uvs1) interpolated at a finished hit on a mesh or
    /// instance whose prototype has one; (0, 0) otherwise.
    [[nodiscard]] glm::vec2 uv1(const Hit& hit) const;

    /// Number of objects.
    [[nodiscard]] std::size_t object_count() const { return objects_.size(); }
    /// Number of prototypes.
    [[nodiscard]] std::size_t prototype_count() const { return prototypes_.size(); }
    /// Number of instances.
    [[nodiscard]] std::size_t instance_count() const { return instances_.size(); }
    /// What object `id` is.
    [[nodiscard]] ObjectKind kind(std::uint32_t id) const { return objects_.at(id).kind; }
    /// The double-precision centre and squared radius sphere object `id`'s intersection
    /// test uses (exactly the geometry rays meet); throws librt::Error unless id is a sphere.
    [[nodiscard]] const DoubleSphere& sphere_geometry(std::uint32_t id) const;
    /// The prototype a mesh or instance object shows; kInvalidId for a sphere.
    [[nodiscard]] std::uint32_t prototype_of(std::uint32_t id) const;
    /// Where instance object `id` puts a prototype-space point: (linear part, translation)
    /// of its object-to-world matrix; identity and zero for every other object.
    [[nodiscard]] std::pair<glm::mat3, glm::vec3> object_to_world(std::uint32_t id) const;
    /// The mesh of a prototype.
    [[nodiscard]] const TriangleMesh& prototype_mesh(std::uint32_t prototype) const {
        return prototypes_.at(prototype).mesh;
    }
    /// The object id of instance `instance` (its rank among add_instance calls).
    [[nodiscard]] std::uint32_t instance_object(std::uint32_t instance) const {
        return instances_.at(instance).object;
    }
    /// Bounding box of all objects (empty if none); valid after build().
    [[nodiscard]] BBox bounds() const { return top_.bounds(); }
    /// Bytes held: prototype meshes and BVHs, spheres, instances, objects and the
    /// structure over them.
    [[nodiscard]] std::size_t memory_bytes() const;

private:
    /// What the traversal dispatches on.
    struct Object {
        ObjectKind kind;
        std::uint16_t flat_bit = 0;  ///< its box's bit in flat_ (0 when not in a flat list)
        std::uint32_t index = 0;     ///< into spheres_, prototypes_ (Mesh) or instances_
    };
    /// A sphere with the double-precision copy its test uses.
    struct SphereData {
        Sphere sphere;
        DoubleSphere prepared;
        bool uv;   ///< see add_sphere
        BBox box;  ///< holds the sphere `prepared` describes
    };
    struct Prototype {
        TriangleMesh mesh;
        TriangleBvh bvh;
        BvhBuilder builder = BvhBuilder::Sah;  ///< how build() builds bvh
    };
    /// An instance's transforms, all derived from object_to_world once.
    struct Instance {
        std::uint32_t prototype;
        std::uint32_t object;       ///< its object id
        glm::mat3 to_object;        ///< linear part of M^-1
        glm::vec3 to_object_shift;  ///< translation of M^-1
        glm::mat3 to_world;         ///< linear part of M
        glm::vec3 to_world_shift;   ///< translation of M
        glm::mat3 normal_matrix;    ///< inverse transpose of to_world
    };
    /// The objects' boxes as plane rows (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z), when there are
    /// at most kFlatObjectLimit; unused slots hold empty boxes, which no ray enters.
    struct FlatBoxes {
        float planes[6][kFlatObjectLimit];
        std::array<std::uint32_t, kFlatObjectLimit> object{};  ///< box i -> object id
        std::uint32_t count = 0;                               ///< 0: use top_
    };

    /// How queries run: the one test every query starts with, so that the flat list of
    /// spheres costs the other lists no instruction.
    enum class Query : std::uint8_t {
        None,     ///< not built: queries throw
        Visit,    ///< visit the boxes of flat_ or top_ nearest first
        Spheres,  ///< every root of sphere_lanes_ at once, ties to Visit
        One,      ///< one mesh or instance: its own BVH, no box (closest_unvisited)
    };
    [[noreturn]] static void throw_not_built();
    /// The closest hit; with kIgnoring, of any object but `ignored_object` (a compile-time
    /// switch: the renderers' query keeps its code).
    /// With kNormal, *normal becomes the hit triangle's winding normal (in its prototype's
    /// space; untouched for a sphere hit).
    template <bool kIgnoring = false, bool kNormal = false>
    bool closest(const Ray& ray, ObjectHit& hit, std::uint32_t ignored_object = kInvalidId,
                 glm::vec3* normal = nullptr) const;
    /// closest() for every query_ but Visit (throws for Query::None): closest_sphere, or the
    /// lone object's own test for Query::One.
    bool closest_unvisited(const Ray& ray, ObjectHit& hit) const;
    /// occluded() for every query_ but Visit, as closest_unvisited.
    bool occluded_unvisited(const Ray& ray, std::uint32_t ignored_object) const;
    /// How a built list is queried: Spheres, One or Visit.
    [[nodiscard]] Query query_for_list() const;
    /// A world ray in an instance's object space.
    static Ray object_ray(const Instance& inst, const Ray& world);
    /// closest() for Query::Spheres (throws for Query::None): the nearest root of the flat
    /// list of spheres, or the visit when two roots are too close to tell apart by float t.
    bool closest_sphere(const Ray& ray, ObjectHit& hit) const;
    /// closest() out of line, for closest_sphere's rare ties.
    bool closest_visit(const Ray& ray, ObjectHit& hit) const;
    /// occluded() for Query::Spheres (throws for Query::None): whether a sphere but object
    /// `ignored_object` has a root.
    bool occluded_sphere(const Ray& ray, std::uint32_t ignored_object) const;
    void check_prototype(std::uint32_t prototype) const;
    std::uint32_t add_object(ObjectKind kind, std::uint32_t index);
    [[nodiscard]] BBox object_bounds(const Object& o) const;
    void finish_instance(const Ray& ray, const Instance& inst, const PrimitiveHit& prim,
                         Hit& hit) const;
    /// The GeometricHit of a hit intersect() returned for `ray`; `winding_normal` is the
    /// triangle's cross(p1 - p0, p2 - p0) in its prototype's space (unused for a sphere).
    void finish_geometric(const Ray& ray, const ObjectHit& object_hit,
                          const glm::vec3& winding_normal, GeometricHit& hit) const;
    /// Calls test_object(object id, ray) -> bool for the objects the ray may hit, nearest
    /// box first (AnyHit: a flat list in object order), through flat_ or top_; stops at
    /// the first hit with AnyHit. The flat list's boxes whose bits are in `skip` are not
    /// visited.
    template <bool AnyHit, class TestObject>
    bool visit_objects(Ray& ray, TestObject&& test_object, std::uint32_t skip = 0) const;

    std::vector<Object> objects_;
    std::vector<SphereData> spheres_;
    std::vector<Prototype> prototypes_;
    std::vector<Instance> instances_;
    std::uint32_t loose_object_ = kInvalidId;  ///< object of the add_triangle mesh

    Bvh top_;  ///< over objects_' boxes
    FlatBoxes flat_;
    /// The flat list's spheres in double, lane i = flat_ box i, when every flat object is a
    /// sphere (else null); immutable once built, so copies share it.
    std::shared_ptr<const detail::SphereLanes> sphere_lanes_;
    /// The kernel of simd_path_ (a detail::SphereRootsFn) when sphere_lanes_ is set; null:
    /// the boxes are visited.
    std::uint32_t (*sphere_roots_)(const detail::SphereLanes&, const DoubleRay&, double, double,
                                   double*) = nullptr;
    SimdPath simd_path_ = default_simd_path();
    std::vector<std::uint32_t> slot_object_;  ///< top_ slot -> object id
    Query query_ = Query::None;
};

}  // namespace librt
