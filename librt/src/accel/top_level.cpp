// The top level's queries: the flat-list-or-BVH traversal (its flat list four boxes at a time), the
// per-object tests and hit finishing. Adding objects and building: top_level_build.cpp.

#include "accel/slab4.h"
#include "accel/sphere_roots.h"
#include "geometry/ray_copy.h"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <librt/accel/bvh_traversal.h>
#include <librt/accel/top_level.h>
#include <librt/core/error.h>
#include <librt/geometry/ray_offset.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <limits>

namespace librt {
namespace {

/// Bound on the part of a sphere hit's o + t d error that grows with the ray's length,
/// relative to t max |d_i| (see finish()).
constexpr float kSphereHitError = 0x1p-21f;

// The unit normal of a triangle from its winding; `fallback` when degenerate.
glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback) {
    const float len2 = glm::dot(v, v);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return fallback;
    return v / std::sqrt(len2);
}

/// The triangle a mesh hit lies on, in the mesh's own space, and the hit's barycentric
/// weights: what finish() and finish_instance() interpolate.
struct TriangleAt {
    const TriangleMesh& mesh;
    const glm::uvec3& idx;
    float b0, b1, b2;
    const glm::vec3& p0;
    const glm::vec3& p1;
    const glm::vec3& p2;
};

// u and v by 4-byte loads: closest() has just stored (t, u) as 8 bytes and v as 4, and g++
// read (u, v) as one 8-byte load across both, which no store forwards to (a stall per mesh
// hit; geometry/ray_copy.h).
[[gnu::always_inline]] inline TriangleAt triangle_at(const TriangleMesh& mesh,
                                                     const PrimitiveHit& prim) {
    const glm::uvec3& idx = mesh.triangles[prim.primitive_id];
    const float b1 = detail::load_alone(prim.u), b2 = detail::load_alone(prim.v);
    return {mesh,
            idx,
            1.0f - b1 - b2,
            b1,
            b2,
            mesh.positions[idx.x],
            mesh.positions[idx.y],
            mesh.positions[idx.z]};
}

/// The rest of a mesh hit once its point and geometric normal are set: the shading normal
/// (the vertex normals, each through `map_normal`, interpolated and turned to the geometric
/// normal's side), the uv (the vertices', or the barycentrics without) and the primitive.
template <class MapNormal>
[[gnu::always_inline]] inline void complete_mesh_hit(const TriangleAt& tri,
                                                     std::uint32_t primitive_id,
                                                     MapNormal&& map_normal, Hit& hit) {
    const TriangleMesh& mesh = tri.mesh;
    const glm::uvec3& idx = tri.idx;
    hit.shading_normal = hit.geometric_normal;
    if (!mesh.normals.empty()) {
        const glm::vec3 n = tri.b0 * map_normal(mesh.normals[idx.x]) +
                            tri.b1 * map_normal(mesh.normals[idx.y]) +
                            tri.b2 * map_normal(mesh.normals[idx.z]);
        const glm::vec3 ns = unit_or(n, hit.geometric_normal);
        hit.shading_normal = glm::dot(ns, hit.geometric_normal) < 0.0f ? -ns : ns;
    }
    hit.uv = mesh.uvs.empty()
                 ? glm::vec2(tri.b1, tri.b2)
                 : tri.b0 * mesh.uvs[idx.x] + tri.b1 * mesh.uvs[idx.y] + tri.b2 * mesh.uvs[idx.z];
    hit.primitive_id = primitive_id;
}

}  // namespace

// Object space, as the visit's tests compute it (the direction is not renormalised, so t
// carries over). Not used by the visit itself: there it made g++ lay the queries out
// differently, +0.2 % instructions on the synthesis.
Ray TopLevel::object_ray(const Instance& inst, const Ray& world) {
    Ray local = world;
    local.origin = inst.to_object * world.origin + inst.to_object_shift;
    local.direction = inst.to_object * world.direction;
    return local;
}

void TopLevel::throw_not_built() {
    throw Error("TopLevel queried before build(): call build() after adding objects");
}

// Forced inline into each query: as a separate call (g++ keeps it out of line) the
// closest-hit lambda's captures and the best hit go through memory (callgrind on the
// synthesis: ~2% of the closest-hit query's instructions).
template <bool AnyHit, class TestObject>
[[gnu::always_inline]] inline bool TopLevel::visit_objects(Ray& ray, TestObject&& test_object,
                                                           std::uint32_t skip) const {
    if (flat_.count == 0)
        return traverse<AnyHit>(top_, ray, [&](std::uint32_t slot, Ray& current) {
            return test_object(slot_object_[slot], current);
        });
    if (!is_traceable(ray)) return false;
    // Entry distance of each box and a bit set per box entered (bbox.h's one conservative
    // slab test, four boxes at a time); bit i clear means box i is missed or visited.
    const std::uint32_t n = flat_.count;
    float enter[kFlatObjectLimit];
    std::uint32_t pending = 0;
    static_assert(kFlatObjectLimit % 4 == 0);
    const detail::SlabRay4 r4 = detail::prepare_slab4(ray);
    for (std::uint32_t i = 0; i < n; i += 4)
        pending |= detail::slab_test4(&flat_.planes[0][i], kFlatObjectLimit, r4, ray.t_min,
                                      ray.t_max, &enter[i])
                   << i;
    pending &= ((1u << n) - 1u) & ~skip;  // n <= 16: the slots past it are empty boxes
    if constexpr (AnyHit) {
        // Any hit ends the query and none moves t_max, so the order changes only the cost:
        // in the order the objects were added (no search for the nearest box), which puts a
        // scene's analytic spheres, cheap to test, before its meshes when added first.
        for (; pending != 0; pending &= pending - 1)
            if (test_object(flat_.object[std::countr_zero(pending)], ray)) return true;
        return false;
    }
    // Visit boxes nearest entry first; stop when the next one starts beyond the nearest hit.
    bool found = false;
    while (pending != 0) {
        std::uint32_t rest = pending;
        std::uint32_t next = std::uint32_t(std::countr_zero(rest));
        float next_enter = enter[next];
        for (rest &= rest - 1; rest != 0; rest &= rest - 1) {
            const auto i = std::uint32_t(std::countr_zero(rest));
            if (enter[i] < next_enter) {
                next_enter = enter[i];
                next = i;
            }
        }
        if (!(next_enter <= ray.t_max)) break;  // the rest all start beyond the nearest hit
        pending &= ~(1u << next);
        if (test_object(flat_.object[next], ray)) {
            found = true;
            if constexpr (AnyHit) return true;
        }
    }
    return found;
}

// Forced inline into both intersect()s: the one that finishes the hit then works on
// registers instead of an ObjectHit passed through memory (the renderers' query, ~1.3% of
// the synthesis' instructions as a separate call).
// The best hit is written straight into `hit`, never copied whole: its fields are stored
// one by one as they are found, and a 16-byte copy of them (ObjectHit by value into
// finish) is a load no store can forward to, a stall per query on the room's sphere hits
// (perf on the synthesis; see docs/benchmarks.md). On a miss `hit` is left as it was.
template <bool kIgnoring, bool kNormal>
[[gnu::always_inline]] inline bool TopLevel::closest(const Ray& ray, ObjectHit& hit,
                                                     std::uint32_t ignored_object,
                                                     [[maybe_unused]] glm::vec3* normal) const {
    Ray r = detail::copy_by_floats(ray);  // no store-forwarding stall (ray_copy.h)
    const DoubleRay dray(r);
    std::uint32_t best_object = kInvalidId;
    PrimitiveHit& best = hit.primitive;
    const auto test_object = [&](std::uint32_t id, Ray& current) {
        if constexpr (kIgnoring) {
            if (id == ignored_object) return false;
        }
        const Object& o = objects_[id];
        if (o.kind == ObjectKind::Sphere) {
            const double t =
                librt::intersect(spheres_[o.index].prepared, dray, current.t_min, current.t_max);
            if (!(t >= 0.0)) return false;
            // Rounding to float may land on t_max itself; keep the interval open.
            float tf = static_cast<float>(t);
            if (!(tf < current.t_max)) tf = std::nextafter(current.t_max, 0.0f);
            current.t_max = tf;
            best = {tf, 0.0f, 0.0f, 0};
        } else {
            PrimitiveHit h;
            if (o.kind == ObjectKind::Mesh) {
                h = prototypes_[o.index].bvh.intersect(current);
            } else {
                // Object space: the direction is not renormalised, so t carries over.
                const Instance& inst = instances_[o.index];
                Ray local = current;
                local.origin = inst.to_object * current.origin + inst.to_object_shift;
                local.direction = inst.to_object * current.direction;
                h = prototypes_[inst.prototype].bvh.intersect(local);
            }
            if (!h.valid()) return false;
            current.t_max = h.t;
            best = h;
        }
        best_object = id;
        return true;
    };
    if constexpr (kNormal) {
        // The same test, the BVH's winding normal of each nearer triangle hit kept in
        // *normal. A lambda of its own: g++ captures what a discarded branch of one lambda
        // names, which cost the renderers' query above a capture (+1 instruction a query).
        glm::vec3& winding = *normal;
        visit_objects<false>(r, [&](std::uint32_t id, Ray& current) {
            const Object& o = objects_[id];
            if (o.kind == ObjectKind::Sphere) return test_object(id, current);
            glm::vec3 n;
            const PrimitiveHit h = o.kind == ObjectKind::Mesh
                                       ? prototypes_[o.index].bvh.intersect(current, n)
                                       : prototypes_[instances_[o.index].prototype].bvh.intersect(
                                             object_ray(instances_[o.index], current), n);
            if (!h.valid()) return false;
            current.t_max = h.t;
            best = h;
            best_object = id;
            winding = n;
            return true;
        });
    } else if constexpr (kIgnoring) {
        // As occluded(): the ignored object's flat box dropped, the test above for top_.
        visit_objects<false>(
            r, test_object,
            ignored_object < objects_.size() ? objects_[ignored_object].flat_bit : 0u);
    } else {
        visit_objects<false>(r, test_object);
    }
    if (best_object == kInvalidId) return false;
    hit.object_id = best_object;
    return true;
}

// Why the nearest root is the hit the box-order visit finds, unless two roots are close:
// that visit accepts a root below the float t_max it has reached, then lowers t_max to the
// root rounded to float (or one float step below the old t_max). With every other root more
// than kTieSteps float steps above the nearest m, each t_max reached stays above m, so m is
// accepted whenever it is visited, and no root after it is. Closer roots (spheres that
// touch, a ray through the seam of two walls) go to the visit itself, whose order decides.
bool TopLevel::closest_sphere(const Ray& ray, ObjectHit& hit) const {
    if (query_ == Query::None) throw_not_built();
    if (!is_traceable(ray)) return false;
    alignas(32) double roots[kFlatObjectLimit];
    const std::uint32_t mask =
        sphere_roots_(*sphere_lanes_, DoubleRay(ray), ray.t_min, ray.t_max, roots);
    if (mask == 0) return false;
        // The nearest root m, its lane and the next root, without a branch on the roots (the
        // lanes that miss hold +inf): a running minimum and second minimum per SSE2 lane, then
        // the two lanes merged. Compare-and-branch here mispredicts on every ray (perf: it
        // was 15 % of the render).
#if defined(__SSE2__)
    const std::uint32_t pairs = (sphere_lanes_->count + 1) / 2;  // every kernel wrote these
    __m128d low = _mm_set1_pd(std::numeric_limits<double>::infinity()), next = low;
    for (std::uint32_t p = 0; p < pairs; ++p) {
        const __m128d v = _mm_load_pd(roots + 2 * p);
        next = _mm_min_pd(next, _mm_max_pd(low, v));
        low = _mm_min_pd(low, v);
    }
    const double low0 = _mm_cvtsd_f64(low), low1 = _mm_cvtsd_f64(_mm_unpackhi_pd(low, low));
    const double next0 = _mm_cvtsd_f64(next), next1 = _mm_cvtsd_f64(_mm_unpackhi_pd(next, next));
    const double m = std::min(low0, low1);
    const double second = std::min(std::max(low0, low1), std::min(next0, next1));
    std::uint32_t at_m = 0;
    const __m128d mm = _mm_set1_pd(m);
    for (std::uint32_t p = 0; p < pairs; ++p)
        at_m |= std::uint32_t(_mm_movemask_pd(_mm_cmpeq_pd(_mm_load_pd(roots + 2 * p), mm)))
                << (2 * p);
    const auto best = std::uint32_t(std::countr_zero(at_m));
#else
    // Unused off x86-64 (no kernel there: sphere_roots_ stays null); kept portable.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::uint32_t best = 0;
    double m = kInf, second = kInf;
    for (std::uint32_t i = 0; i < sphere_lanes_->count; ++i) {
        if (roots[i] < m) {
            second = m;
            m = roots[i];
            best = i;
        } else if (roots[i] < second) {
            second = roots[i];
        }
    }
#endif
    const float mf = static_cast<float>(m);
    // One float step above mf (m >= 0, so the next float is the next bit pattern; from
    // +inf that is a NaN, which sends the ray to the visit).
    const double step = double(std::bit_cast<float>(std::bit_cast<std::uint32_t>(mf) + 1u)) - mf;
    constexpr double kTieSteps = 8.0;
    if (!(second > double(mf) + kTieSteps * step)) return closest_visit(ray, hit);
    // Rounded as the visit rounds it: the interval stays open at t_max.
    float tf = mf;
    if (!(tf < ray.t_max)) tf = std::nextafter(ray.t_max, 0.0f);
    hit.primitive = {tf, 0.0f, 0.0f, 0};
    hit.object_id = flat_.object[best];
    return true;
}

// Out of line: inlined, the visit's registers would be saved and restored around every
// spheres-only query, tie or not (callgrind: ~20 instructions per query).
[[gnu::noinline]] bool TopLevel::closest_visit(const Ray& ray, ObjectHit& hit) const {
    return closest(ray, hit);
}

bool TopLevel::occluded_sphere(const Ray& ray, std::uint32_t ignored_object) const {
    if (query_ == Query::None) throw_not_built();
    if (!is_traceable(ray)) return false;
    alignas(32) double roots[kFlatObjectLimit];
    // Any root will do, in any order.
    for (std::uint32_t mask =
             sphere_roots_(*sphere_lanes_, DoubleRay(ray), ray.t_min, ray.t_max, roots);
         mask != 0; mask &= mask - 1)
        if (flat_.object[std::countr_zero(mask)] != ignored_object) return true;
    return false;
}

// A lone mesh or instance is tested as it is: its BVH tests its root box, so the object's
// box would only repeat that (~120 instructions a ray, 8 % of a query at the bunny). Out of
// line, behind the queries' one test of query_, so that the box visit keeps its code.
bool TopLevel::closest_unvisited(const Ray& ray, ObjectHit& hit) const {
    if (query_ != Query::One) return closest_sphere(ray, hit);
    if (!is_traceable(ray)) return false;
    const std::uint32_t id = flat_.object[0];
    const Object& o = objects_[id];
    const PrimitiveHit h = o.kind == ObjectKind::Mesh
                               ? prototypes_[o.index].bvh.intersect(ray)
                               : prototypes_[instances_[o.index].prototype].bvh.intersect(
                                     object_ray(instances_[o.index], ray));
    if (!h.valid()) return false;
    hit.primitive = h;
    hit.object_id = id;
    return true;
}

bool TopLevel::occluded_unvisited(const Ray& ray, std::uint32_t ignored_object) const {
    if (query_ != Query::One) return occluded_sphere(ray, ignored_object);
    const std::uint32_t id = flat_.object[0];
    if (!is_traceable(ray) || id == ignored_object) return false;
    const Object& o = objects_[id];
    if (o.kind == ObjectKind::Mesh) return prototypes_[o.index].bvh.occluded(ray);
    const Instance& inst = instances_[o.index];
    return prototypes_[inst.prototype].bvh.occluded(object_ray(inst, ray));
}

// Each query's one test of query_ also sends a query before build() to the throw.
bool TopLevel::intersect(const Ray& ray, ObjectHit& hit) const {
    if (query_ != Query::Visit) [[unlikely]]
        return closest_unvisited(ray, hit);
    return closest(ray, hit);
}

bool TopLevel::intersect(const Ray& ray, Hit& hit, bool every_sphere_uv) const {
    ObjectHit h;
    if (query_ != Query::Visit) [[unlikely]] {
        if (!closest_unvisited(ray, h)) return false;
    } else if (!closest(ray, h)) {
        return false;
    }
    finish(ray, h, every_sphere_uv, hit);
    return true;
}

// A lone mesh or instance (Query::One) is tested as closest_unvisited tests it; a flat list
// of spheres by closest_sphere (its normal comes from the sphere); the rest by the visit.
bool TopLevel::intersect(const Ray& ray, GeometricHit& hit) const {
    ObjectHit h;
    glm::vec3 winding(0.0f);
    if (query_ == Query::One) {
        if (!is_traceable(ray)) return false;
        const std::uint32_t id = flat_.object[0];
        const Object& o = objects_[id];
        const PrimitiveHit p = o.kind == ObjectKind::Mesh
                                   ? prototypes_[o.index].bvh.intersect(ray, winding)
                                   : prototypes_[instances_[o.index].prototype].bvh.intersect(
                                         object_ray(instances_[o.index], ray), winding);
        if (!p.valid()) return false;
        h.primitive = p;
        h.object_id = id;
    } else if (query_ != Query::Visit) {
        if (!closest_sphere(ray, h)) return false;  // (throws before build())
    } else if (!closest<false, true>(ray, h, kInvalidId, &winding)) {
        return false;
    }
    finish_geometric(ray, h, winding, hit);
    return true;
}

bool TopLevel::intersect_ignoring(const Ray& ray, Hit& hit, std::uint32_t ignored_object,
                                  bool every_sphere_uv) const {
    if (query_ == Query::None) throw_not_built();
    // The visit serves a flat list of spheres too (closest_visit does, for its ties).
    ObjectHit h;
    if (!closest<true>(ray, h, ignored_object)) return false;
    finish(ray, h, every_sphere_uv, hit);
    return true;
}

bool TopLevel::occluded(const Ray& ray, std::uint32_t ignored_object) const {
    if (query_ != Query::Visit) [[unlikely]]
        return occluded_unvisited(ray, ignored_object);
    Ray r = detail::copy_by_floats(ray);  // no store-forwarding stall (ray_copy.h)
    const DoubleRay dray(r);
    // The ignored object's box is dropped before the visit (a shadow ray toward a sphere
    // light enters the light's box every time); the test below still skips it in top_.
    const std::uint32_t skip =
        ignored_object < objects_.size() ? objects_[ignored_object].flat_bit : 0u;
    return visit_objects<true>(
        r,
        [&](std::uint32_t id, Ray& current) {
            if (id == ignored_object) return false;
            const Object& o = objects_[id];
            switch (o.kind) {
                case ObjectKind::Sphere:
                    return librt::intersect(spheres_[o.index].prepared, dray, current.t_min,
                                            current.t_max) >= 0.0;
                case ObjectKind::Mesh:
                    return prototypes_[o.index].bvh.occluded(current);
                case ObjectKind::Instance:
                    break;
            }
            const Instance& inst = instances_[o.index];
            Ray local = current;
            local.origin = inst.to_object * current.origin + inst.to_object_shift;
            local.direction = inst.to_object * current.direction;
            return prototypes_[inst.prototype].bvh.occluded(local);
        },
        skip);
}

void TopLevel::finish(const Ray& ray, const ObjectHit& object_hit, bool every_sphere_uv,
                      Hit& hit) const {
    const Object& o = objects_[object_hit.object_id];
    const PrimitiveHit& prim = object_hit.primitive;
    hit.t = prim.t;
    hit.object_id = object_hit.object_id;
    hit.instance_id = kInvalidId;
    const glm::vec3 back = -ray.direction;  // fallback orientation for degenerate normals
    if (o.kind == ObjectKind::Sphere) {
        const SphereData& data = spheres_[o.index];
        const Sphere& s = data.sphere;
        hit.point = ray.at(prim.t);
        hit.geometric_normal = unit_or(hit.point - s.center, back);
        // o + t d in float is off the surface by the rounding of t (a double root rounded to
        // float, 2^-24 t |d_i| per coordinate) and of the sum (2^-24 |p_i|, one rounding with
        // a fused multiply-add, 2^-24 t |d_i| more without), so by more with a longer ray
        // than ray_offset_scale(p) covers: a radius-1e5 wall hit near the world origin from
        // 300 away lands up to ~2e-5 off it, against an offset of 5e-6 there (smallpt's
        // corner lost 15 % of its light, issue 41). kSphereHitError t max |d_i| is 4 times
        // the t part's length; ray_offset_scale covers the rest. The next ray's root is
        // solved in double, so the offset need cover nothing else. (Projecting the point
        // onto the sphere in double, as pbrt-v4 re-projects in object space, made the
        // synthesis 5 % slower; so did a bound reading the ray's origin as a vector.)
        const float d_max =
            std::max(std::max(std::fabs(ray.direction.x), std::fabs(ray.direction.y)),
                     std::fabs(ray.direction.z));
        hit.offset = ray_offset_scale(hit.point) + kSphereHitError * prim.t * d_max;
        hit.shading_normal = hit.geometric_normal;
        if (every_sphere_uv || data.uv) {
            // v flipped so that it grows toward +y like OBJ coordinates: images map upright.
            const glm::vec2 uv = librt::sphere_uv(s, hit.point);
            hit.uv = {uv.x, 1.0f - uv.y};
        } else {
            hit.uv = glm::vec2(0.0f);
        }
        hit.primitive_id = 0;
        return;
    }
    if (o.kind == ObjectKind::Instance) {
        finish_instance(ray, instances_[o.index], prim, hit);
        hit.instance_id = o.index;
        return;
    }
    const TriangleAt tri = triangle_at(prototypes_[o.index].mesh, prim);
    // Barycentric interpolation lands closer to the plane than o + t d does.
    hit.point = tri.b0 * tri.p0 + tri.b1 * tri.p1 + tri.b2 * tri.p2;
    hit.offset = barycentric_offset(tri.b0, tri.p0, tri.b1, tri.p1, tri.b2, tri.p2);
    hit.geometric_normal = unit_or(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0), back);
    complete_mesh_hit(
        tri, prim.primitive_id, [](const glm::vec3& n) -> const glm::vec3& { return n; }, hit);
}

// finish()'s t, ids and geometric normal, by the same operations on the same values (the
// leaf's corners are copies of the mesh's), so bit for bit the same.
void TopLevel::finish_geometric(const Ray& ray, const ObjectHit& object_hit,
                                const glm::vec3& winding_normal, GeometricHit& hit) const {
    const Object& o = objects_[object_hit.object_id];
    const PrimitiveHit& prim = object_hit.primitive;
    hit.t = prim.t;
    hit.object_id = object_hit.object_id;
    hit.instance_id = kInvalidId;
    const glm::vec3 back = -ray.direction;
    switch (o.kind) {
        case ObjectKind::Sphere:
            hit.geometric_normal = unit_or(ray.at(prim.t) - spheres_[o.index].sphere.center, back);
            hit.primitive_id = 0;
            return;
        case ObjectKind::Mesh:
            hit.geometric_normal = unit_or(winding_normal, back);
            break;
        case ObjectKind::Instance:
            hit.geometric_normal =
                unit_or(instances_[o.index].normal_matrix * winding_normal, back);
            hit.instance_id = o.index;
            break;
    }
    hit.primitive_id = prim.primitive_id;
}

// Out of line so that the spheres' and meshes' path in finish() stays as lean as it was
// before instances existed (the room's walls are finished millions of times).
[[gnu::noinline]] void TopLevel::finish_instance(const Ray& ray, const Instance& inst,
                                                 const PrimitiveHit& prim, Hit& hit) const {
    const TriangleAt tri = triangle_at(prototypes_[inst.prototype].mesh, prim);
    // The point by the matrix, the winding's normal by the inverse transpose: under a
    // mirroring matrix that is what transform() gives a baked copy, which swaps two corners.
    hit.point =
        inst.to_world * (tri.b0 * tri.p0 + tri.b1 * tri.p1 + tri.b2 * tri.p2) + inst.to_world_shift;
    // The object-space bound (barycentric_offset's sum) carried through |M| and the shift,
    // conservatively: it then also covers the rounding of the next ray's transform into
    // object space, which is about 2^-23 (|M| |p| + |shift|) for a matrix that is not
    // nearly singular.
    const glm::vec3 object_sum =
        glm::abs(tri.b0 * tri.p0) + glm::abs(tri.b1 * tri.p1) + glm::abs(tri.b2 * tri.p2);
    const glm::mat3& m = inst.to_world;
    hit.offset = ray_offset_scale(glm::abs(m[0]) * object_sum.x + glm::abs(m[1]) * object_sum.y +
                                  glm::abs(m[2]) * object_sum.z + glm::abs(inst.to_world_shift));
    hit.geometric_normal =
        unit_or(inst.normal_matrix * glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0), -ray.direction);
    // Each vertex normal mapped and renormalised before interpolation, as transform() does to
    // a baked copy (a zero normal stays zero).
    complete_mesh_hit(
        tri, prim.primitive_id,
        [&](const glm::vec3& n) {
            const glm::vec3 m = inst.normal_matrix * n;
            const float len = glm::length(m);
            return len > 0.0f ? m / len : m;
        },
        hit);
}

}  // namespace librt
