#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/core/error.h>
#include <librt/render/scene.h>

#include <bit>
#include <cmath>
#include <limits>
#include <sstream>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace librt {
namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// A ray in double precision, prepared once per query for the sphere tests.
struct DoubleRay {
    glm::dvec3 origin;
    glm::dvec3 direction;
    double a;      // |direction|^2
    double inv_a;  // 1 / |direction|^2

    explicit DoubleRay(const Ray& r)
        : origin(r.origin),
          direction(r.direction),
          a(glm::dot(direction, direction)),
          inv_a(1.0 / a) {}
};

/// Ray-sphere test in double (the report's walls have radius ~1000, where float loses
/// the root's digits): the quadratic a t^2 + 2 b t + c = 0 with a = |d|^2, b = oc . d,
/// c = |oc|^2 - r^2. Its discriminant / a is r^2 - |oc - (b/a) d|^2, the squared
/// half-chord, free of the cancellation of b^2 - a c; the roots are q / a and c / q with
/// q = -(b + sign(b) sqrt(disc)) (no cancellation either). Returns the nearest root in
/// (t_min, t_max), or a negative value for none (t_min >= 0 for every query).
inline double hit_sphere(const glm::dvec3& center, double radius2, const DoubleRay& ray,
                         double t_min, double t_max) {
    const glm::dvec3 oc = ray.origin - center;
    const double b = glm::dot(oc, ray.direction);
    const double c = glm::dot(oc, oc) - radius2;
    // Outside (c > 0) and moving away (b >= 0): both roots are <= 0 (their product c / a
    // is positive, their sum -2 b / a is not), so no hit. Every ray leaving a sphere's
    // outer surface ends here, without the square root: in the report's room that is each
    // ray from a wall, which starts inside its wall's bounding box.
    if (b >= 0.0 && c > 0.0) return -1.0;
    const glm::dvec3 closest = oc - (b * ray.inv_a) * ray.direction;
    const double half_chord2 = radius2 - glm::dot(closest, closest);
    if (!(half_chord2 >= 0.0)) return -1.0;  // misses (or NaN)
    const double q = -(b + std::copysign(std::sqrt(half_chord2 * ray.a), b));
    const double t_a = q * ray.inv_a;
    const double t_b = q != 0.0 ? c / q : t_a;
    const double near = std::min(t_a, t_b), far = std::max(t_a, t_b);
    if (near > t_min && near < t_max) return near;
    if (far > t_min && far < t_max) return far;
    return -1.0;
}

// The unit normal of a triangle from its winding; `fallback` when degenerate.
glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback) {
    const float len2 = glm::dot(v, v);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return fallback;
    return v / std::sqrt(len2);
}

}  // namespace

std::uint32_t Scene::add_material(const Material& material) {
    validate(material);
    if (material.albedo_texture >= 0 && std::size_t(material.albedo_texture) >= textures_.size()) {
        std::ostringstream msg;
        msg << "material albedo_texture = " << material.albedo_texture << ": only "
            << textures_.size() << " textures in the scene";
        throw Error(msg.str());
    }
    materials_.push_back(material);
    return std::uint32_t(materials_.size() - 1);
}

std::int32_t Scene::add_texture(ImageTexture texture) {
    if (texture.empty()) throw Error("add_texture: the texture is empty");
    textures_.push_back(std::move(texture));
    return std::int32_t(textures_.size() - 1);
}

void Scene::check_material_id(std::uint32_t material) const {
    if (material >= materials_.size()) {
        std::ostringstream msg;
        msg << "material id " << material << ": the scene has " << materials_.size()
            << " materials";
        throw Error(msg.str());
    }
}

std::uint32_t Scene::add_object(ObjectKind kind, std::uint32_t index, std::uint32_t material) {
    committed_ = false;
    objects_.push_back({kind, false, index, material});
    return std::uint32_t(objects_.size() - 1);
}

std::uint32_t Scene::add_sphere(const Sphere& sphere, std::uint32_t material) {
    check_material_id(material);
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
    spheres_.push_back(
        {sphere, glm::dvec3(sphere.center), double(sphere.radius) * double(sphere.radius)});
    return add_object(ObjectKind::Sphere, std::uint32_t(spheres_.size() - 1), material);
}

std::uint32_t Scene::add_triangle(const Triangle& triangle, std::uint32_t material) {
    check_material_id(material);
    if (!finite(triangle.p0) || !finite(triangle.p1) || !finite(triangle.p2))
        throw Error("add_triangle: corners must be finite");
    if (loose_object_ == kInvalidId) {
        meshes_.emplace_back();
        loose_object_ = add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), kInvalidId);
    }
    committed_ = false;
    MeshData& data = meshes_[objects_[loose_object_].index];
    const auto base = std::uint32_t(data.mesh.positions.size());
    data.mesh.positions.insert(data.mesh.positions.end(), {triangle.p0, triangle.p1, triangle.p2});
    data.mesh.triangles.emplace_back(base, base + 1, base + 2);
    data.triangle_materials.push_back(material);
    return loose_object_;
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::uint32_t material) {
    check_material_id(material);
    validate(mesh);
    meshes_.push_back({std::move(mesh), {}, {}});
    return add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), material);
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::uint32_t material, BvhBuilder builder) {
    const std::uint32_t id = add_mesh(std::move(mesh), material);
    meshes_.back().builder = builder;
    return id;
}

std::uint32_t Scene::add_mesh(TriangleMesh mesh, std::vector<std::uint32_t> triangle_materials,
                              BvhBuilder builder) {
    validate(mesh);
    if (triangle_materials.size() != mesh.triangles.size()) {
        throw Error("add_mesh: " + std::to_string(triangle_materials.size()) +
                    " material ids for " + std::to_string(mesh.triangles.size()) + " triangles");
    }
    for (const std::uint32_t m : triangle_materials) check_material_id(m);
    meshes_.push_back({std::move(mesh), {}, std::move(triangle_materials), builder});
    return add_object(ObjectKind::Mesh, std::uint32_t(meshes_.size() - 1), kInvalidId);
}

void Scene::add_point_light(const PointLight& light) {
    validate(light);
    point_lights_.push_back(light);
}

std::uint32_t Scene::add_sphere_light(const SphereLight& light) {
    validate(light);
    const std::uint32_t material = add_material(Material::emissive(light.radiance));
    const std::uint32_t object = add_sphere(light.sphere, material);
    objects_[object].light = true;
    sphere_lights_.push_back(light);
    sphere_light_objects_.push_back(object);
    return object;
}

void Scene::commit() {
    if (committed_) return;
    std::vector<BBox> boxes;
    std::vector<glm::vec3> centers;
    std::vector<std::uint32_t> ids;
    for (std::uint32_t id = 0; id < objects_.size(); ++id) {
        const Object& o = objects_[id];
        BBox box;
        if (o.kind == ObjectKind::Sphere) {
            box = librt::bounds(spheres_[o.index].sphere);
        } else {
            MeshData& m = meshes_[o.index];
            if (m.bvh.triangle_count() != m.mesh.triangle_count() || m.bvh.wide_bvh().empty())
                m.bvh = TriangleBvh(m.mesh, m.builder);
            box = m.bvh.bounds();
        }
        if (box.empty()) continue;  // an empty mesh can be hit by nothing
        boxes.push_back(box);
        centers.push_back(box.center());
        ids.push_back(id);
    }
    unsampled_emitters_ = false;
    for (const Object& o : objects_) {
        if (o.light) continue;
        if (o.material != kInvalidId) {
            unsampled_emitters_ |= materials_[o.material].emits();
        } else {
            for (const std::uint32_t m : meshes_[o.index].triangle_materials)
                unsampled_emitters_ |= materials_[m].emits();
        }
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
    committed_ = true;
}

void Scene::require_committed() const {
    if (!committed_)
        throw Error("Scene queried before commit(): call commit() after adding objects");
}

bool Scene::intersect(const Ray& ray, Hit& hit) const { return intersect_impl(ray, hit, true); }

bool Scene::intersect_for_shading(const Ray& ray, Hit& hit) const {
    return intersect_impl(ray, hit, false);
}

template <bool AnyHit, class TestObject>
bool Scene::visit_objects(Ray& ray, TestObject&& test_object) const {
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

bool Scene::intersect_impl(const Ray& ray, Hit& hit, bool sphere_uv_always) const {
    require_committed();
    Ray r = ray;
    const DoubleRay dray(ray);
    std::uint32_t best_object = kInvalidId;
    PrimitiveHit best;
    visit_objects<false>(r, [&](std::uint32_t id, Ray& current) {
        const Object& o = objects_[id];
        if (o.kind == ObjectKind::Sphere) {
            const SphereData& s = spheres_[o.index];
            const double t = hit_sphere(s.center, s.radius2, dray, current.t_min, current.t_max);
            if (!(t >= 0.0)) return false;
            // Rounding to float may land on t_max itself; keep the interval open.
            float tf = static_cast<float>(t);
            if (!(tf < current.t_max)) tf = std::nextafter(current.t_max, 0.0f);
            current.t_max = tf;
            best = {tf, 0.0f, 0.0f, 0};
        } else {
            const PrimitiveHit h = meshes_[o.index].bvh.intersect(current);
            if (!h.valid()) return false;
            current.t_max = h.t;
            best = h;
        }
        best_object = id;
        return true;
    });
    if (best_object == kInvalidId) return false;
    finish_hit(ray, best_object, best, sphere_uv_always, hit);
    return true;
}

bool Scene::occluded(const Ray& ray, std::uint32_t ignored_object) const {
    require_committed();
    Ray r = ray;
    const DoubleRay dray(ray);
    return visit_objects<true>(r, [&](std::uint32_t id, Ray& current) {
        if (id == ignored_object) return false;
        const Object& o = objects_[id];
        if (o.kind == ObjectKind::Sphere) {
            const SphereData& s = spheres_[o.index];
            return hit_sphere(s.center, s.radius2, dray, current.t_min, current.t_max) >= 0.0;
        }
        return meshes_[o.index].bvh.occluded(current);
    });
}

void Scene::finish_hit(const Ray& ray, std::uint32_t object_id, const PrimitiveHit& prim,
                       bool sphere_uv_always, Hit& hit) const {
    const Object& o = objects_[object_id];
    hit.t = prim.t;
    hit.object_id = object_id;
    const glm::vec3 back = -ray.direction;  // fallback orientation for degenerate normals
    if (o.kind == ObjectKind::Sphere) {
        const Sphere& s = spheres_[o.index].sphere;
        hit.point = ray.at(prim.t);
        hit.geometric_normal = unit_or(hit.point - s.center, back);
        hit.shading_normal = hit.geometric_normal;
        if (sphere_uv_always || materials_[o.material].albedo_texture >= 0) {
            // v flipped so that it grows toward +y like OBJ coordinates: images map upright.
            const glm::vec2 uv = sphere_uv(s, hit.point);
            hit.uv = {uv.x, 1.0f - uv.y};
        } else {
            hit.uv = glm::vec2(0.0f);
        }
        hit.primitive_id = 0;
        return;
    }
    const TriangleMesh& mesh = meshes_[o.index].mesh;
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

std::uint32_t Scene::material_id(const Hit& hit) const {
    const Object& o = objects_[hit.object_id];
    if (o.material != kInvalidId) return o.material;
    return meshes_[o.index].triangle_materials[hit.primitive_id];
}

glm::vec3 Scene::albedo(const Hit& hit) const {
    const Material& m = material(hit);
    if (m.albedo_texture >= 0) return textures_[std::size_t(m.albedo_texture)].lookup(hit.uv);
    return m.albedo;
}

}  // namespace librt
