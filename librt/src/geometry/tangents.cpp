#include <librt/geometry/tangents.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt {
namespace {

// Unit v, or zero when v has no usable length.
glm::vec3 unit_or_zero(const glm::vec3& v) {
    const float len = glm::length(v);
    return len > 0.0f && std::isfinite(len) ? v / len : glm::vec3(0.0f);
}

// The angle at corner a of triangle (a, b, c).
float corner_angle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 e1 = unit_or_zero(b - a), e2 = unit_or_zero(c - a);
    return std::acos(std::clamp(glm::dot(e1, e2), -1.0f, 1.0f));
}

}  // namespace

std::vector<glm::vec4> generate_tangents(const TriangleMesh& mesh, bool v_down) {
    const std::size_t n = mesh.positions.size();
    if (mesh.uvs.size() != n || n == 0) return {};
    // Vertex normals: the mesh's, else angle-weighted face normals.
    std::vector<glm::vec3> normals = mesh.normals;
    if (normals.size() != n) {
        normals.assign(n, glm::vec3(0.0f));
        for (const glm::uvec3& t : mesh.triangles) {
            const glm::vec3 fn =
                unit_or_zero(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                        mesh.positions[t.z] - mesh.positions[t.x]));
            for (int k = 0; k < 3; ++k)
                normals[t[k]] +=
                    fn * corner_angle(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]],
                                      mesh.positions[t[(k + 2) % 3]]);
        }
        for (glm::vec3& v : normals) v = unit_or_zero(v);
    }
    std::vector<glm::vec3> tan(n, glm::vec3(0.0f)), bitan(n, glm::vec3(0.0f));
    const float v_sign = v_down ? -1.0f : 1.0f;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec3 e1 = mesh.positions[t.y] - mesh.positions[t.x];
        const glm::vec3 e2 = mesh.positions[t.z] - mesh.positions[t.x];
        const glm::vec2 d1 = mesh.uvs[t.y] - mesh.uvs[t.x], d2 = mesh.uvs[t.z] - mesh.uvs[t.x];
        // Solve [e1 e2] = [T B] [d1 d2] for the directions of increasing u (T) and v (B)
        // (Lengyel 2001); v_sign turns glTF's downward v into the image's upward one.
        const float du1 = d1.x, dv1 = v_sign * d1.y, du2 = d2.x, dv2 = v_sign * d2.y;
        const float r = du1 * dv2 - du2 * dv1;
        if (!(std::fabs(r) > 0.0f) || !std::isfinite(r)) continue;  // degenerate uvs
        const glm::vec3 ft = (e1 * dv2 - e2 * dv1) / r;
        const glm::vec3 fb = (e2 * du1 - e1 * du2) / r;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = t[k];
            const glm::vec3& nv = normals[v];
            const float w = corner_angle(mesh.positions[v], mesh.positions[t[(k + 1) % 3]],
                                         mesh.positions[t[(k + 2) % 3]]);
            tan[v] += w * unit_or_zero(ft - glm::dot(ft, nv) * nv);
            bitan[v] += w * unit_or_zero(fb - glm::dot(fb, nv) * nv);
        }
    }
    std::vector<glm::vec4> out(n);
    for (std::size_t v = 0; v < n; ++v) {
        const glm::vec3& nv = normals[v];
        glm::vec3 t = unit_or_zero(tan[v] - glm::dot(tan[v], nv) * nv);  // Gram-Schmidt
        if (t == glm::vec3(0.0f)) {
            // Any direction perpendicular to the normal (or x for a zero normal).
            const glm::vec3 a = std::fabs(nv.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
            t = unit_or_zero(a - glm::dot(a, nv) * nv);
            if (t == glm::vec3(0.0f)) t = glm::vec3(1, 0, 0);
            out[v] = glm::vec4(t, 1.0f);
            continue;
        }
        const float w = glm::dot(glm::cross(nv, t), bitan[v]) < 0.0f ? -1.0f : 1.0f;
        out[v] = glm::vec4(t, w);
    }
    return out;
}

}  // namespace librt
