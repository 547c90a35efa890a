// The top level's construction: adding spheres, prototypes, meshes and instances (with
// their validation and matrices), building, and memory accounting. Queries: top_level.cpp.

#include "accel/sphere_roots.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/top_level.h>
#include <librt/core/error.h>
#include <librt/core/finite.h>

#include <glm/ext/matrix_double3x3.hpp>
#include <glm/ext/matrix_double4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

namespace librt {
namespace {

// Relative padding of an instance's world box: 2^-18 of its largest coordinate, as
// ray_offset_scale; far above the few ulps by which the float ray transform and the
// rounded corners can disagree, far below any feature.
constexpr double kInstanceBoxPad = 0x1p-18;

}  // namespace

std::uint32_t TopLevel::add_object(ObjectKind kind, std::uint32_t index) {
    query_ = Query::None;
    objects_.push_back({kind, 0, index});
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
    spheres_.push_back({sphere, DoubleSphere(sphere), uv, librt::bounds(sphere)});
    return add_object(ObjectKind::Sphere, std::uint32_t(spheres_.size() - 1));
}

std::uint32_t TopLevel::add_sphere(const glm::dvec3& center, double radius, bool uv) {
    const Sphere rounded{glm::vec3(center), static_cast<float>(radius)};
    if (!std::isfinite(center.x) || !std::isfinite(center.y) || !std::isfinite(center.z) ||
        !finite(rounded.center)) {
        std::ostringstream msg;
        msg.precision(17);
        msg << "sphere center = (" << center.x << ", " << center.y << ", " << center.z
            << "): must be finite (in float too)";
        throw Error(msg.str());
    }
    if (!std::isfinite(radius) || !(radius > 0.0) || !std::isfinite(rounded.radius) ||
        !(rounded.radius > 0.0f)) {
        std::ostringstream msg;
        msg.precision(17);
        msg << "sphere radius = " << radius << ": must be finite and > 0 (in float too)";
        throw Error(msg.str());
    }
    spheres_.push_back({rounded, DoubleSphere(center, radius), uv, librt::bounds(center, radius)});
    return add_object(ObjectKind::Sphere, std::uint32_t(spheres_.size() - 1));
}

std::uint32_t TopLevel::add_prototype(TriangleMesh mesh, BvhBuilder builder) {
    validate(mesh);
    query_ = Query::None;
    prototypes_.push_back({std::move(mesh), {}, builder});
    return std::uint32_t(prototypes_.size() - 1);
}

std::uint32_t TopLevel::add_triangle(const Triangle& triangle) {
    if (!finite(triangle.p0) || !finite(triangle.p1) || !finite(triangle.p2))
        throw Error("add_triangle: corners must be finite");
    if (loose_object_ == kInvalidId) loose_object_ = add_mesh(add_prototype({}));
    query_ = Query::None;
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

std::pair<glm::mat3, glm::vec3> TopLevel::object_to_world(std::uint32_t id) const {
    const Object& o = objects_.at(id);
    if (o.kind != ObjectKind::Instance) return {glm::mat3(1.0f), glm::vec3(0.0f)};
    return {instances_[o.index].to_world, instances_[o.index].to_world_shift};
}

const DoubleSphere& TopLevel::sphere_geometry(std::uint32_t id) const {
    const Object& o = objects_.at(id);
    if (o.kind != ObjectKind::Sphere)
        throw Error("sphere_geometry: object " + std::to_string(id) + " is not a sphere");
    return spheres_[o.index].prepared;
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
            return spheres_[o.index].box;
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
    if (built()) return;
    for (Prototype& p : prototypes_) {
        if (p.bvh.triangle_count() != p.mesh.triangle_count() || p.bvh.empty())
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
    for (Object& o : objects_) o.flat_bit = 0;
    if (ids.size() <= kFlatObjectLimit) {
        flat_.count = std::uint32_t(ids.size());
        for (std::size_t i = 0; i < kFlatObjectLimit; ++i) {  // empty boxes: never entered
            for (int a = 0; a < 3; ++a) {
                flat_.planes[2 * a][i] = std::numeric_limits<float>::infinity();
                flat_.planes[2 * a + 1][i] = -std::numeric_limits<float>::infinity();
            }
        }
        for (std::size_t i = 0; i < ids.size(); ++i) {
            for (int a = 0; a < 3; ++a) {
                flat_.planes[2 * a][i] = boxes[i].lo[a];
                flat_.planes[2 * a + 1][i] = boxes[i].hi[a];
            }
            flat_.object[i] = ids[i];
            objects_[ids[i]].flat_bit = static_cast<std::uint16_t>(1u << i);
        }
    }
    sphere_lanes_.reset();
    const auto is_sphere = [&](std::uint32_t id) {
        return objects_[id].kind == ObjectKind::Sphere;
    };
    if (flat_.count > 0 && std::all_of(ids.begin(), ids.end(), is_sphere)) {
        auto lanes = std::make_shared<detail::SphereLanes>();
        lanes->clear();
        for (std::uint32_t i = 0; i < flat_.count; ++i)
            lanes->push(spheres_[objects_[flat_.object[i]].index].prepared);
        sphere_lanes_ = std::move(lanes);
    }
    sphere_roots_ = sphere_lanes_ ? detail::sphere_roots_for(simd_path_) : nullptr;
    query_ = query_for_list();
}

TopLevel::Query TopLevel::query_for_list() const {
    if (sphere_roots_ != nullptr) return Query::Spheres;
    return flat_.count == 1 ? Query::One : Query::Visit;  // a lone sphere is a list of spheres
}

void TopLevel::set_simd_path(SimdPath path) {
    if (!simd_path_supported(path))
        throw Error(std::string("TopLevel: SIMD path ") + to_string(path) +
                    " is not supported here");
    simd_path_ = path;
    sphere_roots_ = sphere_lanes_ ? detail::sphere_roots_for(path) : nullptr;
    if (built()) query_ = query_for_list();
}

std::size_t TopLevel::memory_bytes() const {
    std::size_t bytes = sizeof(*this);
    for (const Prototype& p : prototypes_) {
        const TriangleMesh& m = p.mesh;
        bytes +=
            sizeof(Prototype) + p.bvh.memory_bytes() + m.positions.capacity() * sizeof(glm::vec3) +
            m.triangles.capacity() * sizeof(glm::uvec3) + m.normals.capacity() * sizeof(glm::vec3) +
            m.uvs.capacity() * sizeof(glm::vec2) + m.uvs1.capacity() * sizeof(glm::vec2) +
            m.material_ids.capacity() * sizeof(std::uint32_t) +
            m.materials.capacity() * sizeof(MeshMaterial);
    }
    bytes += spheres_.capacity() * sizeof(SphereData) + instances_.capacity() * sizeof(Instance) +
             objects_.capacity() * sizeof(Object) + top_.nodes.capacity() * sizeof(BvhNode) +
             top_.prim_indices.capacity() * sizeof(std::uint32_t) +
             slot_object_.capacity() * sizeof(std::uint32_t);
    return bytes;
}

}  // namespace librt
