#pragma once

#include <librt/accel/bvh.h>
#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_stats.h>
#include <librt/accel/simd.h>
#include <librt/export.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/geometry/triangle.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace librt {

namespace detail {
struct WideBvh;  // the private node layout (librt/src/accel/wide_bvh.h)
}  // namespace detail

/// The binned-SAH settings TriangleBvh builds with (BvhBuilder::Sah): leaves are costed
/// in blocks of four triangles (the leaf block of the SIMD kernels) and hold at most two
/// blocks.
[[nodiscard]] LIBRT_API SahConfig triangle_sah_config();

/// Closest-hit and any-hit queries over a triangle mesh through an 8-wide BVH (collapsed
/// from the chosen binary builder's tree) whose leaves hold the triangles in blocks of four,
/// tested with SIMD kernels picked at run time (see simd.h). Hits report the mesh's own
/// triangle index and the exact t of triangle.h's watertight test, whatever the path.
/// Queries may run concurrently from any number of threads (set_simd_path aside). Copies
/// share the immutable tree.
class LIBRT_API TriangleBvh {
public:
    TriangleBvh() = default;
    /// Builds over all triangles of the mesh. Throws librt::Error for an index out of
    /// range or a non-finite position.
    explicit TriangleBvh(const TriangleMesh& mesh, BvhBuilder builder = BvhBuilder::Sah);
    /// Builds over loose triangles (primitive id = index in the span).
    explicit TriangleBvh(std::span<const Triangle> triangles, BvhBuilder builder = BvhBuilder::Sah);

    /// Nearest hit with t in (ray.t_min, ray.t_max), if any.
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// intersect(ray), and on a hit `winding_normal` set to the hit triangle's
    /// cross(p1 - p0, p2 - p0) (not unit; zero for a degenerate triangle), computed from the
    /// leaf's copy of its corners: the mesh is not read. On a miss `winding_normal` is left.
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray, glm::vec3& winding_normal) const;
    /// True when anything lies in (ray.t_min, ray.t_max): for shadow rays.
    [[nodiscard]] bool occluded(const Ray& ray) const;

    /// A stream of rays: hits[i] = intersect(rays[i]) for every i, bit for bit (t, u, v and
    /// primitive id; a ray that is not traceable, e.g. with a NaN t_max or t_min > t_max,
    /// misses as it does alone). Over a tree of 8 MiB or more (memory_bytes()), a stream
    /// whose first rays are not coherent (not each within a degree of the one before) is
    /// walked eight rays at a time, their node visits interleaved so that the core overlaps
    /// their memory and dependency latencies: 1.1-1.2x the single rays' rate on incoherent
    /// and shadow rays over the 0.9M-triangle dragon and a 1M-triangle teapot. Otherwise
    /// (smaller trees, coherent rays: there the interleaving measured slower) it is a loop
    /// over the single-ray query. docs/benchmarks.md, "Ray streams", has the figures. Any
    /// number of rays, none included. Throws librt::Error naming both sizes when
    /// hits.size() != rays.size(). The spans must not overlap.
    void intersect(std::span<const Ray> rays, std::span<PrimitiveHit> hits) const;
    /// A stream of shadow rays: blocked[i] = occluded(rays[i]) ? 1 : 0 for every i, as
    /// intersect(rays, hits) is for closest hits. Throws librt::Error naming both sizes when
    /// blocked.size() != rays.size().
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const;

    /// True for a BVH over no triangles, which nothing hits.
    [[nodiscard]] bool empty() const { return tree_ == nullptr; }
    /// Box around all triangles (empty for an empty BVH).
    [[nodiscard]] BBox bounds() const { return bounds_; }
    /// Number of triangles built over (the mesh's, or the span's, size).
    [[nodiscard]] std::size_t triangle_count() const { return triangle_count_; }
    /// Node, leaf, depth and memory figures of the 8-wide tree (a leaf is a run of blocks of
    /// four triangles; its size counts triangles), by one walk over its nodes.
    [[nodiscard]] BvhStats stats() const;
    /// What intersect(ray) (any_hit false) or occluded(ray) (true) does: nodes, leaves and
    /// triangles tested, by a separate counting instantiation of the same traversal (slower;
    /// the counts are those of every SIMD path, which all make the same decisions).
    [[nodiscard]] TraversalCounts count_traversal(const Ray& ray, bool any_hit) const;
    /// Bytes of the wide BVH and its triangle blocks (stats().bytes without the walk).
    [[nodiscard]] std::size_t memory_bytes() const;

    /// The instruction set intersect() and occluded() use; default_simd_path() at first.
    [[nodiscard]] SimdPath simd_path() const { return path_; }
    /// Switches instruction set (every path gives the same results); throws librt::Error
    /// when simd_path_supported(path) is false.
    void set_simd_path(SimdPath path);

private:
    void build(std::span<const Triangle> triangles, BvhBuilder builder);

    friend const detail::WideBvh* wide_bvh_of(const TriangleBvh& bvh);

    std::shared_ptr<const detail::WideBvh> tree_;  ///< null when empty; copies share it
    BBox bounds_;
    std::size_t triangle_count_ = 0;
    SimdPath path_ = SimdPath::Scalar;
    PrimitiveHit (*intersect_fn_)(const detail::WideBvh&, const Ray&) = nullptr;
    bool (*occluded_fn_)(const detail::WideBvh&, const Ray&) = nullptr;
    // (The normal's entry point is looked up from path_ per query, not stored: one more
    // pointer here cost the renderers' query 0.03 % more instructions on cornell_pbr.glb.)
};

/// The naive alternative with the same interface: tests every triangle for every ray.
/// Kept for tests (ground truth) and benchmarks (the thing a BVH must beat).
class LIBRT_API TriangleList {
public:
    TriangleList() = default;
    /// Copies all triangles of the mesh (primitive id = triangle index). Throws
    /// librt::Error for an index out of range or a non-finite position.
    explicit TriangleList(const TriangleMesh& mesh);
    /// Copies loose triangles (primitive id = index in the span).
    explicit TriangleList(std::span<const Triangle> triangles);

    /// Nearest hit with t in (ray.t_min, ray.t_max), if any.
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// True when anything lies in (ray.t_min, ray.t_max).
    [[nodiscard]] bool occluded(const Ray& ray) const;
    /// Number of triangles held.
    [[nodiscard]] std::size_t triangle_count() const { return triangles_.size(); }

private:
    std::vector<Triangle> triangles_;
};

}  // namespace librt
