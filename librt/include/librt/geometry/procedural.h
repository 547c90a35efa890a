#pragma once

#include <librt/export.h>
#include <librt/geometry/mesh.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>

namespace librt {

/// Most vertices a procedural generator makes (2^26, about 2 GiB with normals and uvs):
/// larger requests throw librt::Error before allocating.
inline constexpr std::uint64_t kMaxProceduralVertices = std::uint64_t{1} << 26u;

/// A UV sphere with unit outward normals and uvs matching sphere_uv (u = azimuth around +y,
/// v = 0 at the +y pole). segments (>= 3) around the axis, rings (>= 2) from pole to pole:
/// (rings + 1)(segments + 1) vertices (seam and poles repeated for the uvs) and
/// 2 segments (rings - 1) triangles (none degenerate). Throws librt::Error naming the parameter
/// on bad parameters (segments and rings at most 2^15, at most kMaxProceduralVertices vertices).
[[nodiscard]] LIBRT_API TriangleMesh make_uv_sphere(const glm::vec3& center, float radius,
                                                    int segments, int rings);

/// An icosahedron subdivided `subdivisions` times (0..10), every vertex on the sphere:
/// 10 * 4^s + 2 vertices and 20 * 4^s triangles, with unit outward normals and no uvs.
/// Throws librt::Error on bad parameters.
[[nodiscard]] LIBRT_API TriangleMesh make_icosphere(const glm::vec3& center, float radius,
                                                    int subdivisions);

/// The parallelogram corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v as two
/// triangles facing edge_u x edge_v, with that unit normal and uvs (0,0) (1,0) (1,1) (0,1).
/// Throws librt::Error if the edges are parallel or zero.
[[nodiscard]] LIBRT_API TriangleMesh make_quad(const glm::vec3& corner, const glm::vec3& edge_u,
                                               const glm::vec3& edge_v);

/// The axis-aligned box [lo, hi] as 12 outward-facing triangles, 4 vertices per face so each
/// face has its own flat normal and (0..1)^2 uvs. Throws librt::Error unless lo < hi.
[[nodiscard]] LIBRT_API TriangleMesh make_box(const glm::vec3& lo, const glm::vec3& hi);

/// Patches in the Utah teapot: rim 4, body 8, handle 4, spout 4, lid 8, bottom 4.
inline constexpr int teapot_patch_count = 32;

/// Triangles make_teapot(n) returns: 2 n^2 per patch.
[[nodiscard]] constexpr std::size_t teapot_triangle_count(int tessellation) {
    const auto n = static_cast<std::size_t>(tessellation);
    return 2 * teapot_patch_count * n * n;
}

/// The Utah (Newell) teapot from its 32 published bicubic Bezier patches (rim, body, handle,
/// spout, lid and the later-added bottom), each evaluated on an (n+1) x (n+1) grid of its
/// parameters (1 <= n <= 4096): 32 (n+1)^2 vertices and exactly 64 n^2 triangles, wound
/// counter-clockwise seen from outside.
/// - Normals are analytic (dP/dv x dP/du of the patch, unit, outward). Where a derivative
///   vanishes (the lid's knob and the bottom's centre, where a patch edge collapses to a
///   point) the normal is the limit taken a tiny step inside the patch, i.e. the axis.
/// - Those collapsed edges make 8 n triangles of zero area (n per lid-top and bottom patch;
///   at n = 1 also the 4 of the spout's lip, whose corners are collinear); they are kept so
///   the count is exactly 64 n^2. Patches are not welded to each other.
/// - uvs are the patch parameters (u along the patch's rows, v along its columns) in [0,1]^2.
/// - Orientation and size: +y up (the data's z), the spout towards +x, the handle towards -x,
///   bounding box centred on the origin and scaled so x spans exactly [-1, 1] (the surface's
///   extremes: handle at -1, spout lip at +1); then y spans [-0.4896, 0.4896] (the bottom at
///   -0.4896, the lid's knob at +0.4896) and z spans [-0.6217, 0.6217] (the body).
///   Coarse grids may fall slightly inside these bounds, never outside.
/// Throws librt::Error if tessellation is out of range or the mesh would have more than
/// kMaxProceduralVertices vertices (tessellation above 1447).
[[nodiscard]] LIBRT_API TriangleMesh make_teapot(int tessellation);

/// The smallest tessellation n with teapot_triangle_count(n) >= target triangles, i.e.
/// ceil(sqrt(target / 64)), at least 1. Throws librt::Error if it would exceed 4096.
[[nodiscard]] LIBRT_API int teapot_tessellation_for(std::size_t target);

/// make_teapot(teapot_tessellation_for(target)): at least `target` triangles, e.g. for
/// benchmarks at 1k, 10k, ... 1M+ triangles.
[[nodiscard]] LIBRT_API TriangleMesh make_teapot_with_triangles(std::size_t target);

}  // namespace librt
