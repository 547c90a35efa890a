#pragma once

#include <librt/export.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/triangle.h>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace librt {

/// A material as read from an OBJ's MTL file; the renderer maps it to its own materials.
struct MeshMaterial {
    std::string name;             ///< newmtl name, as usemtl refers to it
    glm::vec3 diffuse{0.8f};      ///< Kd
    glm::vec3 specular{0.0f};     ///< Ks
    glm::vec3 emission{0.0f};     ///< Ke
    float ior = 1.0f;             ///< Ni
    float dissolve = 1.0f;        ///< d (1 = opaque)
    int illum = 2;                ///< MTL illumination model
    std::string diffuse_texture;  ///< map_Kd, resolved to a path relative to the working directory;
                                  ///< empty if none
    /// Where it was defined, "file.mtl:line" of its newmtl, for messages about it (the name
    /// alone does not say which file); empty for a material not read from a file.
    std::string defined_at;
};

/// An indexed triangle mesh. Per-vertex attributes share the positions' indexing;
/// optional arrays are either empty or exactly as long as the array they annotate.
struct LIBRT_API TriangleMesh {
    std::vector<glm::vec3> positions;   ///< vertex positions, in the mesh's space
    std::vector<glm::uvec3> triangles;  ///< three indices into positions per triangle
    std::vector<glm::vec3> normals;     ///< optional, one per position
    std::vector<glm::vec2> uvs;         ///< optional, one per position
    /// Optional, one per position: a second uv set, read by texture slots whose uv_set is 1
    /// (glTF's other TEXCOORD_n); kept only by meshes whose material uses it.
    std::vector<glm::vec2> uvs1;
    /// Optional, one per position: tangent xyz (along increasing u) and w = +-1, the
    /// bitangent's sign: bitangent = w cross(normal, tangent) (glTF TANGENT). For normal maps.
    std::vector<glm::vec4> tangents;
    /// Optional, one per position: a linear RGBA colour (glTF COLOR_0) that multiplies the
    /// material's base colour (its albedo for other kinds) and coverage where a hit lands.
    std::vector<glm::vec4> colors;
    std::vector<std::uint32_t> material_ids;  ///< optional, one per triangle, into materials
    std::vector<MeshMaterial> materials;      ///< from the MTL file, may be empty

    /// Number of triangles (size of triangles).
    [[nodiscard]] std::size_t triangle_count() const { return triangles.size(); }
    /// Number of vertices (size of positions).
    [[nodiscard]] std::size_t vertex_count() const { return positions.size(); }
    /// The corners of triangle i.
    [[nodiscard]] Triangle triangle(std::size_t i) const {
        const glm::uvec3& t = triangles[i];
        return {positions[t.x], positions[t.y], positions[t.z]};
    }
    /// Bounding box of all positions.
    [[nodiscard]] BBox bounds() const;
};

/// Applies an affine transform to positions (and the inverse transpose to normals, renormalised;
/// tangents by the matrix, renormalised, their w negated by a mirroring matrix).
/// A mirroring matrix (negative determinant) also swaps two corners of every triangle, so the
/// winding's normal keeps agreeing with the shading normals. Throws librt::Error, leaving the
/// mesh untouched, if an entry is not finite, the bottom row is not (0 0 0 1), or the mesh
/// has normals and the matrix is singular. (Positions that overflow to infinity under a
/// huge scale are not checked here: validate() reports them.)
LIBRT_API void transform(TriangleMesh& mesh, const glm::mat4& matrix);

/// Scale, then rotate (angles in degrees about x, then y, then z), then translate:
/// the report's "scaled by 20 and moved by (0, -10, 0)". Throws librt::Error naming the
/// argument when one is not finite.
[[nodiscard]] LIBRT_API glm::mat4 make_transform(const glm::vec3& scale,
                                                 const glm::vec3& rotation_degrees,
                                                 const glm::vec3& translation);

/// The largest |coordinate| a mesh position may have, 2^40 (about 1.1e12). The watertight
/// triangle test computes a distance from products of three coordinate differences in
/// float: with corners and ray origins within +-2^40 these stay below 2^127, beyond it they
/// overflow and the triangle is silently missed (a triangle 2e18 wide seen from distance 55
/// is). validate() refuses positions outside this range; docs/robustness.md has the details.
inline constexpr float kMaxMeshCoordinate = 1099511627776.0f;  // 2^40

/// Throws librt::Error naming the problem (and the offending index) when triangle or material
/// indices are out of range, optional arrays have the wrong length, positions, normals, uvs,
/// tangents or colors are not finite, or a position lies outside +-kMaxMeshCoordinate.
LIBRT_API void validate(const TriangleMesh& mesh);

}  // namespace librt
