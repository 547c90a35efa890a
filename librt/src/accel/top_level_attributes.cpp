// Surface attributes of a finished hit that finish() does not interpolate (tangents), for
// the few materials that need them; kept out of top_level.cpp's hot query path.

#include <librt/accel/top_level.h>
#include <librt/geometry/tangents.h>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>

namespace librt {

glm::vec2 TopLevel::barycentrics(const Hit& hit) const {
    const Object& o = objects_.at(hit.object_id);
    if (o.kind == ObjectKind::Sphere) return glm::vec2(0.0f);
    glm::vec3 p = hit.point;
    std::uint32_t prototype = o.index;
    if (o.kind == ObjectKind::Instance) {
        const Instance& inst = instances_[o.index];
        p = inst.to_object * p + inst.to_object_shift;
        prototype = inst.prototype;
    }
    const TriangleMesh& mesh = prototypes_[prototype].mesh;
    const glm::uvec3& idx = mesh.triangles.at(hit.primitive_id);
    const glm::vec3 a = mesh.positions[idx.x];
    // Barycentrics of a point in the triangle's plane by Cramer's rule on the normal
    // equations (Ericson, Real-Time Collision Detection, 2005, sec. 3.4).
    const glm::vec3 e1 = mesh.positions[idx.y] - a, e2 = mesh.positions[idx.z] - a, d = p - a;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float dp1 = glm::dot(d, e1), dp2 = glm::dot(d, e2);
    const float denom = d11 * d22 - d12 * d12;
    if (!(denom > 0.0f)) return glm::vec2(0.0f);
    return {(d22 * dp1 - d12 * dp2) / denom, (d11 * dp2 - d12 * dp1) / denom};
}

glm::vec4 TopLevel::tangent(const Hit& hit) const {
    const Object& o = objects_.at(hit.object_id);
    if (o.kind == ObjectKind::Sphere) return glm::vec4(0.0f);
    const Instance* inst = o.kind == ObjectKind::Instance ? &instances_[o.index] : nullptr;
    const TriangleMesh& mesh = prototypes_[inst ? inst->prototype : o.index].mesh;
    if (mesh.tangents.empty()) return glm::vec4(0.0f);
    const glm::vec2 b = barycentrics(hit);
    const glm::uvec3& idx = mesh.triangles.at(hit.primitive_id);
    const glm::vec4 &t0 = mesh.tangents[idx.x], &t1 = mesh.tangents[idx.y],
                    &t2 = mesh.tangents[idx.z];
    glm::vec3 t = (1.0f - b.x - b.y) * glm::vec3(t0) + b.x * glm::vec3(t1) + b.y * glm::vec3(t2);
    // The handedness of the corner with the largest weight (corners of one triangle agree
    // in any sane mesh; this picks one without averaging signs).
    const float w = b.x > 0.5f ? t1.w : (b.y > 0.5f ? t2.w : t0.w);
    float sign = w < 0.0f ? -1.0f : 1.0f;
    if (inst != nullptr) {
        t = inst->to_world * t;
        // A mirroring instance flips cross(normal, tangent) against the mapped bitangent.
        if (glm::determinant(inst->to_world) < 0.0f) sign = -sign;
    }
    return glm::vec4(t, sign);
}

void TopLevel::generate_prototype_tangents(std::uint32_t prototype, bool v_down) {
    check_prototype(prototype);
    TriangleMesh& mesh = prototypes_[prototype].mesh;
    // Uvs that are all one point (the glTF loader's stand-in for a missing TEXCOORD) give
    // no frame: generate_tangents would return an arbitrary one, so there are none, and a
    // normal map or anisotropy direction falls back as on a mesh without uvs.
    const auto varies = [&](const glm::vec2& uv) { return uv != mesh.uvs.front(); };
    if (mesh.tangents.empty() && !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size() &&
        std::any_of(mesh.uvs.begin(), mesh.uvs.end(), varies))
        mesh.tangents = generate_tangents(mesh, v_down);  // shading data: the BVH stays
}

glm::vec2 TopLevel::uv1(const Hit& hit) const {
    const Object& o = objects_.at(hit.object_id);
    if (o.kind == ObjectKind::Sphere) return glm::vec2(0.0f);
    const std::uint32_t p =
        o.kind == ObjectKind::Instance ? instances_[o.index].prototype : o.index;
    const TriangleMesh& mesh = prototypes_[p].mesh;
    if (mesh.uvs1.empty()) return glm::vec2(0.0f);
    const glm::vec2 b = barycentrics(hit);
    const glm::uvec3& idx = mesh.triangles.at(hit.primitive_id);
    return (1.0f - b.x - b.y) * mesh.uvs1[idx.x] + b.x * mesh.uvs1[idx.y] + b.y * mesh.uvs1[idx.z];
}

bool TopLevel::has_colors(std::uint32_t id) const {
    const Object& o = objects_.at(id);
    if (o.kind == ObjectKind::Sphere) return false;
    const std::uint32_t p =
        o.kind == ObjectKind::Instance ? instances_[o.index].prototype : o.index;
    return !prototypes_[p].mesh.colors.empty();
}

glm::vec4 TopLevel::color(const Hit& hit) const {
    if (!has_colors(hit.object_id)) return glm::vec4(1.0f);
    const Object& o = objects_[hit.object_id];
    const std::uint32_t p =
        o.kind == ObjectKind::Instance ? instances_[o.index].prototype : o.index;
    const TriangleMesh& mesh = prototypes_[p].mesh;
    const glm::vec2 b = barycentrics(hit);
    const glm::uvec3& idx = mesh.triangles.at(hit.primitive_id);
    return (1.0f - b.x - b.y) * mesh.colors[idx.x] + b.x * mesh.colors[idx.y] +
           b.y * mesh.colors[idx.z];
}

}  // namespace librt
