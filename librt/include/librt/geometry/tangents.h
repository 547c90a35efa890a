#pragma once

#include <librt/export.h>
#include <librt/geometry/mesh.h>

#include <glm/vec4.hpp>

#include <vector>

namespace librt {

/// Per-vertex tangents for a mesh without them (glTF TANGENT's layout: xyz along
/// increasing u, w = +-1 with bitangent = w cross(normal, tangent) along increasing v),
/// from its uvs: per triangle, the tangent and bitangent that the uv derivatives give
/// (Lengyel 2001, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh"); at each
/// corner both are projected onto the plane of the vertex normal, normalised and weighted
/// by the corner's angle (as MikkTSpace weighs them), summed per vertex; the sum is made
/// perpendicular to the normal (Gram-Schmidt) and w is the side the summed bitangent lies
/// on. Vertex normals are the mesh's, or the angle-weighted face normals when it has none.
///
/// Close to MikkTSpace, not bit-compatible with it: MikkTSpace also splits a vertex shared
/// by triangles of opposite handedness and merges vertices with equal position, normal and
/// uv; here each vertex index keeps one tangent. `v_down`: the uvs are glTF's (v runs
/// down the image), so "increasing v" for the bitangent means up the image, i.e. -v.
/// A vertex whose triangles all have degenerate uvs gets any unit tangent perpendicular to
/// its normal, w = 1. Returns an empty vector when the mesh has no uvs.
[[nodiscard]] LIBRT_API std::vector<glm::vec4> generate_tangents(const TriangleMesh& mesh,
                                                                 bool v_down);

}  // namespace librt
