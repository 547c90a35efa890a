// The top level: object storage, the flat-list-or-BVH traversal (with its SSE flat list)
// and hit finishing. Over ~400 lines because the three share the object layout and the
// traversal must inline the per-object tests to keep the room's speed.

#include <librt/accel/bvh_traversal.h>
#include <librt/accel/top_level.h>
#include <librt/core/error.h>

#include <glm/ext/matrix_double3x3.hpp>
#include <glm/ext/matrix_double4x4.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <bit>
#include <cmath>
#include <sstream>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace librt {
namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The unit normal of a triangle from its winding; `fallback` when degenerate.
glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback) {
    const float len2 = glm::dot(v, v);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return fallback;
    return v / std::sqrt(len2);
}

// Relative padding of an instance's world box: 2^-18 of its largest coordinate, as
// ray_offset_scale; far above the few ulps by which the float ray transform and the
// rounded corners can disagree, far below any feature.
constexpr double kInstanceBoxPad = 0x1p-18;

}  // namespace

std::uint32_t TopLevel::add_object(ObjectKind kind, std::uint32_t index) {
    built_ = false;
    objects_.push_back({kind, index});
    return std::uint32_t(objects_.size() - 1);
}

void TopLevel::check_prototype(std::uint32_t prototype) const {
    if (prototype >= prototypes_.size()) {
        std::ostringstream msg;
        msg << "prototype id " << prototype << ": there are " << prototypes_.size()
            << " mesh prototypes";
        throw Error(msg.str());
    }
}

std::uint32_t TopLevel::add_sphere(const Sphere& sphere, bool uv) {
    if (!finite(sphere.center)) {
        std::ostringstream msg;
        msg << "sphere center = (" << sphere.center.x << ", " << sphere.center.y << ", "
            << sphere.center.z << "): must be finite";
        throw Error(msg.str());
    }
    if (!std::isfinite(sphere.radius) || !(sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere radius = " << sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    spheres_.push_back({sphere, DoubleSphere(sphere), uv});
    return add_object(ObjectKind::Sphere, std::uint32_t(spheres_.size() - 1));
}

std::uint32_t TopLevel::add_prototype(TriangleMesh mesh, BvhBuilder builder) {
    validate(mesh);
    built_ = false;
    prototypes_.push_back({std::move(mesh), {}, builder});
    return std::uint32_t(prototypes_.size() - 1);
}

std::uint32_t TopLevel::add_triangle(const Triangle& triangle) {
    if (!finite(triangle.p0) || !finite(triangle.p1) || !finite(triangle.p2))
        throw Error("add_triangle: corners must be finite");
    if (loose_object_ == kInvalidId) loose_object_ = add_mesh(add_prototype({}));
    built_ = false;
    TriangleMesh& mesh = prototypes_[objects_[loose_object_].index].mesh;
    const auto base = std::uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {triangle.p0, triangle.p1, triangle.p2});
    mesh.triangles.emplace_back(base, base + 1, base + 2);
    return loose_object_;
}

std::uint32_t TopLevel::add_mesh(std::uint32_t prototype) {
    check_prototype(prototype);
    return add_object(ObjectKind::Mesh, prototype);
}

std::uint32_t TopLevel::add_instance(std::uint32_t prototype, const glm::mat4& object_to_world) {
    check_prototype(prototype);
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(object_to_world[c][r])) {
                throw Error("add_instance: object_to_world entry (row " + std::to_string(r) +
                            ", column " + std::to_string(c) +
                            ") = " + std::to_string(object_to_world[c][r]) + ": must be finite");
            }
        }
    }
    // GLM is column-major: m[c][r]; the bottom row is m[c][3].
    if (object_to_world[0][3] != 0.0f || object_to_world[1][3] != 0.0f ||
        object_to_world[2][3] != 0.0f || object_to_world[3][3] != 1.0f)
        throw Error("add_instance: object_to_world is not affine (bottom row must be 0 0 0 1)");
    // Inverses in double: the float matrices then carry one rounding each.
    const glm::dmat3 linear{glm::dmat4(object_to_world)};
    const double det = glm::determinant(linear);
    const glm::dmat3 inverse = glm::inverse(linear);
    const glm::dvec3 shift{glm::dvec4(object_to_world[3])};
    const glm::dvec3 inverse_shift = -(inverse * shift);
    bool invertible = det != 0.0 && std::isfinite(det);
    for (int c = 0; c < 3; ++c)
        invertible =
            invertible && finite(glm::vec3(inverse[c])) && finite(glm::vec3(inverse_shift));
    if (!invertible) {
        std::ostringstream msg;
        msg << "add_instance: object_to_world is singular (det = " << det << ")";
        throw Error(msg.str());
    }
    Instance inst;
    inst.prototype = prototype;
    inst.object = std::uint32_t(objects_.size());
    inst.to_object = glm::mat3(inverse);
    inst.to_object_shift = glm::vec3(inverse_shift);
    inst.to_world = glm::mat3(linear);
    inst.to_world_shift = glm::vec3(shift);
    // Normals transform by the inverse transpose so they stay perpendicular to tangents.
    inst.normal_matrix = glm::mat3(glm::transpose(inverse));
    instances_.push_back(inst);
    return add_object(ObjectKind::Instance, std::uint32_t(instances_.size() - 1));
}

std::uint32_t TopLevel::prototype_of(std::uint32_t id) const {
    const Object& o = objects_.at(id);
    switch (o.kind) {
        case ObjectKind::Mesh:
            return o.index;
        case ObjectKind::Instance:
            return instances_[o.index].prototype;
        case ObjectKind::Sphere:
            break;
    }
    return kInvalidId;
}

BBox TopLevel::object_bounds(const Object& o) const {
    switch (o.kind) {
        case ObjectKind::Sphere:
            return librt::bounds(spheres_[o.index].sphere);
        case ObjectKind::Mesh:
            return prototypes_[o.index].bvh.bounds();
        case ObjectKind::Instance:
            break;
    }
    const Instance& inst = instances_[o.index];
    const BBox local = prototypes_[inst.prototype].bvh.bounds();
    if (local.empty()) return local;
    // The eight corners mapped in double, then padded (see kInstanceBoxPad).
    const glm::dmat3 m(inst.to_world);
    const glm::dvec3 shift(inst.to_world_shift);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1) ? local.hi.x : local.lo.x,
                           (corner & 2) ? local.hi.y : local.lo.y,
                           (corner & 4) ? local.hi.z : local.lo.z);
        const glm::dvec3 q = m * p + shift;
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    const double largest = glm::max(
        glm::max(glm::abs(lo), glm::abs(hi)).x,
        glm::max(glm::max(glm::abs(lo), glm::abs(hi)).y, glm::max(glm::abs(lo), glm::abs(hi)).z));
    const double pad = kInstanceBoxPad * largest + 0x1p-20;
    return {glm::vec3(lo - pad), glm::vec3(hi + pad)};
}

void TopLevel::build() {
    if (built_) return;
    for (Prototype& p : prototypes_) {
        if (p.bvh.triangle_count() != p.mesh.triangle_count() || p.bvh.wide_bvh().empty())
            p.bvh = TriangleBvh(p.mesh, p.builder);
    }
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centers;
    std::vector<std::uint32_t> ids;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        const BBox box = object_bounds(objects_[id]);
        if (box.empty()) continue;  // an empty mesh can be hit by nothing
        boxes.push_back(box);
        centers.push_back(box.center());
        ids.push_back(id);
    }
    top_ = build_sah_bvh(boxes, centers);
    slot_object_.resize(top_.prim_indices.size());
    for (std::size_t slot = 0; slot < slot_object_.size(); ++slot)
        slot_object_[slot] = ids[top_.prim_indices[slot]];
    flat_.count = 0;
    if (ids.size() <= kFlatObjectLimit) {
        flat_.count = std::uint32_t(ids.size());
        for (std::size_t i = 0; i < ids.size(); ++i) {
            flat_.lo_x[i] = boxes[i].lo.x;
            flat_.lo_y[i] = boxes[i].lo.y;
            flat_.lo_z[i] = boxes[i].lo.z;
            flat_.hi_x[i] = boxes[i].hi.x;
            flat_.hi_y[i] = boxes[i].hi.y;
            flat_.hi_z[i] = boxes[i].hi.z;
            flat_.object[i] = ids[i];
        }
    }
    built_ = true;
}

void TopLevel::require_built() const {
    if (!built_) throw Error("TopLevel queried before build(): call build() after adding objects");
}

std::size_t TopLevel::memory_bytes() const {
    std::size_t bytes = sizeof(*this);
    for (const Prototype& p : prototypes_) {
        const TriangleMesh& m = p.mesh;
        bytes += sizeof(Prototype) + p.bvh.memory_bytes() +
                 m.positions.capacity() * sizeof(glm::vec3) +
                 m.triangles.capacity() * sizeof(glm::uvec3) +
                 m.normals.capacity() * sizeof(glm::vec3) + m.uvs.capacity() * sizeof(glm::vec2) +
                 m.material_ids.capacity() * sizeof(std::uint32_t) +
                 m.materials.capacity() * sizeof(MeshMaterial);
    }
    bytes += spheres_.capacity() * sizeof(SphereData) + instances_.capacity() * sizeof(Instance) +
             objects_.capacity() * sizeof(Object) + top_.nodes.capacity() * sizeof(BvhNode) +
             top_.prim_indices.capacity() * sizeof(std::uint32_t) +
             slot_object_.capacity() * sizeof(std::uint32_t);
    return bytes;
}

template <bool AnyHit, class TestObject>
bool TopLevel::visit_objects(Ray& ray, TestObject&& test_object) const {
    if (flat_.count == 0)
        return traverse<AnyHit>(top_, ray, [&](std::uint32_t slot, Ray& current) {
            return test_object(slot_object_[slot], current);
        });
    if (!is_traceable(ray)) return false;
    const glm::vec3 inv = safe_inverse(ray.direction);
    const glm::vec3& o = ray.origin;
    // Entry distance of each box and a bit set per box entered (the slab test of bbox.h,
    // exit widened by kSlabExitSlack); bit i clear means box i is missed or visited.
    const std::uint32_t n = flat_.count;
    float enter[kFlatObjectLimit];
    std::uint32_t pending = 0;
#if defined(__SSE2__)
    // Four boxes at a time, each min/max the scalar version's with its operands swapped
    // (_mm_min_ps(b, a) is std::min(a, b), _mm_max_ps(b, a) is std::max(a, b)): the same
    // result for every input, NaN included.
    static_assert(kFlatObjectLimit % 4 == 0);
    const __m128 ox = _mm_set1_ps(o.x), oy = _mm_set1_ps(o.y), oz = _mm_set1_ps(o.z);
    const __m128 ix = _mm_set1_ps(inv.x), iy = _mm_set1_ps(inv.y), iz = _mm_set1_ps(inv.z);
    const __m128 t_min = _mm_set1_ps(ray.t_min), t_max = _mm_set1_ps(ray.t_max);
    const __m128 sign_bit = _mm_set1_ps(-0.0f), slack = _mm_set1_ps(kSlabExitSlack);
    for (std::uint32_t i = 0; i < n; i += 4) {
        const __m128 x0 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.lo_x[i]), ox), ix);
        const __m128 x1 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.hi_x[i]), ox), ix);
        const __m128 y0 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.lo_y[i]), oy), iy);
        const __m128 y1 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.hi_y[i]), oy), iy);
        const __m128 z0 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.lo_z[i]), oz), iz);
        const __m128 z1 = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(&flat_.hi_z[i]), oz), iz);
        const __m128 t_in = _mm_max_ps(_mm_max_ps(t_min, _mm_min_ps(z1, z0)),
                                       _mm_max_ps(_mm_min_ps(y1, y0), _mm_min_ps(x1, x0)));
        __m128 far =
            _mm_min_ps(_mm_max_ps(z1, z0), _mm_min_ps(_mm_max_ps(y1, y0), _mm_max_ps(x1, x0)));
        far = _mm_add_ps(far, _mm_mul_ps(_mm_andnot_ps(sign_bit, far), slack));  // |far| slack
        const __m128 t_out = _mm_min_ps(t_max, far);
        _mm_storeu_ps(&enter[i], t_in);
        pending |= std::uint32_t(_mm_movemask_ps(_mm_cmple_ps(t_in, t_out))) << i;
    }
    pending &= (1u << n) - 1u;  // n <= 16: the slots past it are zero boxes
#else
    for (std::uint32_t i = 0; i < n; ++i) {
        const float x0 = (flat_.lo_x[i] - o.x) * inv.x, x1 = (flat_.hi_x[i] - o.x) * inv.x;
        const float y0 = (flat_.lo_y[i] - o.y) * inv.y, y1 = (flat_.hi_y[i] - o.y) * inv.y;
        const float z0 = (flat_.lo_z[i] - o.z) * inv.z, z1 = (flat_.hi_z[i] - o.z) * inv.z;
        const float t_in = std::max(std::max(std::min(x0, x1), std::min(y0, y1)),
                                    std::max(std::min(z0, z1), ray.t_min));
        float far = std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::max(z0, z1));
        far += std::fabs(far) * kSlabExitSlack;  // never lose a box to rounding (bbox.h)
        const float t_out = std::min(far, ray.t_max);
        enter[i] = t_in;
        pending |= std::uint32_t(t_in <= t_out) << i;
    }
#endif
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

bool TopLevel::intersect(const Ray& ray, ObjectHit& hit) const {
    require_built();
    return closest(ray, hit);
}

bool TopLevel::intersect(const Ray& ray, Hit& hit, bool every_sphere_uv) const {
    require_built();
    ObjectHit h;
    if (!closest(ray, h)) return false;
    finish(ray, h, every_sphere_uv, hit);
    return true;
}

bool TopLevel::closest(const Ray& ray, ObjectHit& hit) const {
    Ray r = ray;
    const DoubleRay dray(ray);
    std::uint32_t best_object = kInvalidId;
    PrimitiveHit best;
    visit_objects<false>(r, [&](std::uint32_t id, Ray& current) {
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
    });
    if (best_object == kInvalidId) return false;
    hit.object_id = best_object;
    hit.primitive = best;
    return true;
}

bool TopLevel::occluded(const Ray& ray, std::uint32_t ignored_object) const {
    require_built();
    Ray r = ray;
    const DoubleRay dray(ray);
    return visit_objects<true>(r, [&](std::uint32_t id, Ray& current) {
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
    });
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
    const TriangleMesh& mesh = prototypes_[o.index].mesh;
    const glm::uvec3& idx = mesh.triangles[prim.primitive_id];
    const float b1 = prim.u, b2 = prim.v, b0 = 1.0f - prim.u - prim.v;
    const glm::vec3& p0 = mesh.positions[idx.x];
    const glm::vec3& p1 = mesh.positions[idx.y];
    const glm::vec3& p2 = mesh.positions[idx.z];
    // Barycentric interpolation lands closer to the plane than o + t d does.
    hit.point = b0 * p0 + b1 * p1 + b2 * p2;
    hit.geometric_normal = unit_or(glm::cross(p1 - p0, p2 - p0), back);
    hit.shading_normal = hit.geometric_normal;
    if (!mesh.normals.empty()) {
        const glm::vec3 n =
            b0 * mesh.normals[idx.x] + b1 * mesh.normals[idx.y] + b2 * mesh.normals[idx.z];
        const glm::vec3 ns = unit_or(n, hit.geometric_normal);
        hit.shading_normal = glm::dot(ns, hit.geometric_normal) < 0.0f ? -ns : ns;
    }
    hit.uv = mesh.uvs.empty() ? glm::vec2(b1, b2)
                              : b0 * mesh.uvs[idx.x] + b1 * mesh.uvs[idx.y] + b2 * mesh.uvs[idx.z];
    hit.primitive_id = prim.primitive_id;
}

// Out of line so that the spheres' and meshes' path in finish() stays as lean as it was
// before instances existed (the room's walls are finished millions of times).
[[gnu::noinline]] void TopLevel::finish_instance(const Ray& ray, const Instance& inst,
                                                 const PrimitiveHit& prim, Hit& hit) const {
    const TriangleMesh& mesh = prototypes_[inst.prototype].mesh;
    const glm::uvec3& idx = mesh.triangles[prim.primitive_id];
    const float b1 = prim.u, b2 = prim.v, b0 = 1.0f - prim.u - prim.v;
    const glm::vec3& p0 = mesh.positions[idx.x];
    const glm::vec3& p1 = mesh.positions[idx.y];
    const glm::vec3& p2 = mesh.positions[idx.z];
    // The point by the matrix, the winding's normal by the inverse transpose: under a
    // mirroring matrix that is what transform() gives a baked copy, which swaps two corners.
    hit.point = inst.to_world * (b0 * p0 + b1 * p1 + b2 * p2) + inst.to_world_shift;
    hit.geometric_normal =
        unit_or(inst.normal_matrix * glm::cross(p1 - p0, p2 - p0), -ray.direction);
    hit.shading_normal = hit.geometric_normal;
    if (!mesh.normals.empty()) {
        // Each vertex normal mapped and renormalised before interpolation, as transform()
        // does to a baked copy (a zero normal stays zero).
        const auto map = [&](const glm::vec3& n) {
            const glm::vec3 m = inst.normal_matrix * n;
            const float len = glm::length(m);
            return len > 0.0f ? m / len : m;
        };
        const glm::vec3 n = b0 * map(mesh.normals[idx.x]) + b1 * map(mesh.normals[idx.y]) +
                            b2 * map(mesh.normals[idx.z]);
        const glm::vec3 ns = unit_or(n, hit.geometric_normal);
        hit.shading_normal = glm::dot(ns, hit.geometric_normal) < 0.0f ? -ns : ns;
    }
    hit.uv = mesh.uvs.empty() ? glm::vec2(b1, b2)
                              : b0 * mesh.uvs[idx.x] + b1 * mesh.uvs[idx.y] + b2 * mesh.uvs[idx.z];
    hit.primitive_id = prim.primitive_id;
}

}  // namespace librt
