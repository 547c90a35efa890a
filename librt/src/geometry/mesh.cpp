#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/geometry/mesh.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

namespace librt {

namespace {

std::string to_string(const glm::vec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) +
           ")";
}

}  // namespace

BBox TriangleMesh::bounds() const {
    BBox b;
    for (const glm::vec3& p : positions) b.extend(p);
    return b;
}

void transform(TriangleMesh& mesh, const glm::mat4& matrix) {
    // Checked before anything moves, so a bad matrix leaves the mesh untouched.
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(matrix[c][r])) {
                throw Error("transform: matrix entry (row " + std::to_string(r) + ", column " +
                            std::to_string(c) + ") = " + std::to_string(matrix[c][r]) +
                            ": must be finite");
            }
        }
    }
    // GLM is column-major: matrix[c][r]; the bottom row is matrix[c][3].
    if (matrix[0][3] != 0.0f || matrix[1][3] != 0.0f || matrix[2][3] != 0.0f ||
        matrix[3][3] != 1.0f) {
        throw Error("transform: matrix is not affine (bottom row must be 0 0 0 1)");
    }
    const glm::mat3 linear(matrix);
    const glm::vec3 translation(matrix[3]);
    const float det = glm::determinant(linear);
    if (!mesh.normals.empty() && (!(det != 0.0f) || !std::isfinite(det))) {
        throw Error("transform: matrix is singular (det = " + std::to_string(det) +
                    "), normals cannot be transformed");
    }
    for (glm::vec3& p : mesh.positions) p = linear * p + translation;

    if (!mesh.normals.empty()) {
        // Normals transform by the inverse transpose so they stay perpendicular to tangents.
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
        for (glm::vec3& n : mesh.normals) {
            const glm::vec3 m = normal_matrix * n;
            const float len = glm::length(m);
            n = len > 0.0f ? m / len : m;  // a zero normal stays zero rather than NaN
        }
    }
    for (glm::vec4& t : mesh.tangents) {
        // Tangents are directions in the surface: they map by the matrix itself. A mirror
        // flips cross(normal, tangent) against the mapped bitangent, hence w's sign.
        const glm::vec3 m = linear * glm::vec3(t);
        const float len = glm::length(m);
        t = glm::vec4(len > 0.0f ? m / len : m, det < 0.0f ? -t.w : t.w);
    }
    // A mirror reverses the winding; swap two corners so the geometric normal
    // (p1 - p0) x (p2 - p0) keeps agreeing with the shading normals.
    if (det < 0.0f) {
        for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    }
}

glm::mat4 make_transform(const glm::vec3& scale, const glm::vec3& rotation_degrees,
                         const glm::vec3& translation) {
    const auto check = [](const char* name, const glm::vec3& v) {
        if (!finite(v)) {
            throw Error(std::string("make_transform: ") + name + " = " + to_string(v) +
                        ": must be finite");
        }
    };
    check("scale", scale);
    check("rotation_degrees", rotation_degrees);
    check("translation", translation);
    // M = T * Rz * Ry * Rx * S: applied right to left to a point.
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translation);
    m = glm::rotate(m, glm::radians(rotation_degrees.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotation_degrees.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotation_degrees.x), glm::vec3(1, 0, 0));
    return glm::scale(m, scale);
}

void validate(const TriangleMesh& mesh) {
    const std::size_t n = mesh.positions.size();
    if (!mesh.normals.empty() && mesh.normals.size() != n) {
        throw Error("mesh: " + std::to_string(mesh.normals.size()) + " normals for " +
                    std::to_string(n) + " positions (must be 0 or equal)");
    }
    if (!mesh.uvs.empty() && mesh.uvs.size() != n) {
        throw Error("mesh: " + std::to_string(mesh.uvs.size()) + " uvs for " + std::to_string(n) +
                    " positions (must be 0 or equal)");
    }
    if (!mesh.uvs1.empty() && mesh.uvs1.size() != n) {
        throw Error("mesh: " + std::to_string(mesh.uvs1.size()) + " second-set uvs for " +
                    std::to_string(n) + " positions (must be 0 or equal)");
    }
    if (!mesh.colors.empty() && mesh.colors.size() != n) {
        throw Error("mesh: " + std::to_string(mesh.colors.size()) + " colors for " +
                    std::to_string(n) + " positions (must be 0 or equal)");
    }
    if (!mesh.tangents.empty() && mesh.tangents.size() != n) {
        throw Error("mesh: " + std::to_string(mesh.tangents.size()) + " tangents for " +
                    std::to_string(n) + " positions (must be 0 or equal)");
    }
    if (!mesh.material_ids.empty() && mesh.material_ids.size() != mesh.triangles.size()) {
        throw Error("mesh: " + std::to_string(mesh.material_ids.size()) + " material ids for " +
                    std::to_string(mesh.triangles.size()) + " triangles (must be 0 or equal)");
    }
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = mesh.positions[i];
        if (!finite(p)) {
            throw Error("mesh: position " + std::to_string(i) + " is not finite " + to_string(p));
        }
        if (std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) > kMaxMeshCoordinate) {
            char text[96];
            std::snprintf(text, sizeof text, "(%g, %g, %g)", double(p.x), double(p.y), double(p.z));
            throw Error("mesh: position " + std::to_string(i) + " = " + text +
                        " is outside the representable range |coordinate| <= 2^40 (1.1e12): "
                        "ray distances to it would overflow float and it would never be hit");
        }
    }
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        if (!finite(mesh.normals[i])) {
            throw Error("mesh: normal " + std::to_string(i) + " is not finite " +
                        to_string(mesh.normals[i]));
        }
    }
    for (std::size_t i = 0; i < mesh.uvs.size(); ++i) {
        if (!finite(mesh.uvs[i])) {
            throw Error("mesh: uv " + std::to_string(i) + " is not finite");
        }
    }
    for (std::size_t i = 0; i < mesh.uvs1.size(); ++i) {
        if (!finite(mesh.uvs1[i])) {
            throw Error("mesh: second-set uv " + std::to_string(i) + " is not finite");
        }
    }
    for (std::size_t i = 0; i < mesh.colors.size(); ++i) {
        const glm::vec4& c = mesh.colors[i];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) ||
            !std::isfinite(c.w)) {
            throw Error("mesh: color " + std::to_string(i) + " is not finite");
        }
    }
    for (std::size_t i = 0; i < mesh.tangents.size(); ++i) {
        const glm::vec4& t = mesh.tangents[i];
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
            !std::isfinite(t.w)) {
            throw Error("mesh: tangent " + std::to_string(i) + " is not finite");
        }
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const glm::uvec3& t = mesh.triangles[i];
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= n) {
                throw Error("mesh: triangle " + std::to_string(i) + " index " +
                            std::to_string(t[k]) + " is out of range (" + std::to_string(n) +
                            " positions)");
            }
        }
    }
    for (std::size_t i = 0; i < mesh.material_ids.size(); ++i) {
        if (mesh.material_ids[i] >= mesh.materials.size()) {
            throw Error("mesh: triangle " + std::to_string(i) + " material id " +
                        std::to_string(mesh.material_ids[i]) + " is out of range (" +
                        std::to_string(mesh.materials.size()) + " materials)");
        }
    }
}

}  // namespace librt
