#include "core/parallel.h"
#include "wide_bvh.h"
#include "wide_kernels.h"

#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <thread>

namespace librt {
namespace {

/// Runs body(begin, end) over [0, n) split between the hardware threads (inline when n is
/// small).
template <class Body>
void parallel_ranges(std::size_t n, Body&& body) {
    detail::parallel_parts(n, detail::threads_for(n),
                           [&](unsigned, std::size_t begin, std::size_t end) { body(begin, end); });
}

/// The mesh's triangles as a flat array, first touched by the threads that fill it.
struct MeshTriangles {
    detail::LargeBuffer<Triangle> data;
    std::size_t count = 0;
    [[nodiscard]] std::span<const Triangle> span() const { return {data.get(), count}; }
};

MeshTriangles mesh_triangles(const TriangleMesh& mesh) {
    // A bad index would read outside positions, a NaN corner would vanish from its box
    // (min and max drop NaN): refuse both. (Error and std::to_string come with
    // bvh_traversal.h.)
    const std::size_t n = mesh.positions.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error("mesh: position " + std::to_string(i) + " is not finite");
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const glm::uvec3& t = mesh.triangles[i];
        if (t.x >= n || t.y >= n || t.z >= n) {
            const std::uint32_t bad = t.x >= n ? t.x : t.y >= n ? t.y : t.z;
            throw Error("mesh: triangle " + std::to_string(i) + " index " + std::to_string(bad) +
                        " is out of range (" + std::to_string(n) + " positions)");
        }
    }
    MeshTriangles tris{detail::make_large_buffer<Triangle>(mesh.triangle_count()),
                       mesh.triangle_count()};
    parallel_ranges(tris.count, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            std::construct_at(&tris.data[i], mesh.triangle(i));
    });
    return tris;
}

/// The triangles, after checking every corner is finite.
std::span<const Triangle> checked(std::span<const Triangle> triangles) {
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& t = triangles[i];
        const float sum =
            t.p0.x + t.p0.y + t.p0.z + t.p1.x + t.p1.y + t.p1.z + t.p2.x + t.p2.y + t.p2.z;
        if (!std::isfinite(sum)) {
            // The sum also overflows for huge finite corners; name the real culprit.
            for (const glm::vec3& p : {t.p0, t.p1, t.p2})
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    throw Error("triangle " + std::to_string(i) + " has a non-finite corner");
        }
    }
    return triangles;
}

/// Leaf callback of the linear scan: tests the triangle in a slot (its index) and records
/// it as the nearest so far.
struct NearestTriangle {
    const Triangle* triangles;
    WatertightRay prepared;
    PrimitiveHit hit;

    bool operator()(std::uint32_t slot, Ray& ray) {
        const auto h = librt::intersect(triangles[slot], prepared, ray.t_min, ray.t_max);
        if (!h) return false;
        ray.t_max = h->t;
        hit = {h->t, h->u, h->v, slot};
        return true;
    }
};

}  // namespace

// Leaves are tested four triangles at a time: the leaf cost counts blocks of four
// (B(n) = ceil(n / 4)), and a block test costs about as much as a wide node's box test.
SahConfig triangle_sah_config() {
    SahConfig config;
    config.leaf_block_size = detail::kTriangleBlockSize;
    config.max_leaf_size = 2 * detail::kTriangleBlockSize;
    config.traversal_cost = 1.0f;
    config.intersection_cost = 1.0f;
    return config;
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh, BvhBuilder builder) {
    const MeshTriangles tris = mesh_triangles(mesh);
    build(tris.span(), builder);
}

TriangleBvh::TriangleBvh(std::span<const Triangle> triangles, BvhBuilder builder) {
    build(checked(triangles), builder);
}

void TriangleBvh::build(std::span<const Triangle> triangles, BvhBuilder builder) {
    const std::size_t n = triangles.size();
    const detail::LargeBuffer<BBox> box_buffer = detail::make_large_buffer<BBox>(n);
    const detail::LargeBuffer<glm::vec3> center_buffer = detail::make_large_buffer<glm::vec3>(n);
    const std::span<BBox> boxes(box_buffer.get(), n);
    const std::span<glm::vec3> centers(center_buffer.get(), n);
    parallel_ranges(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            std::construct_at(&boxes[i], librt::bounds(triangles[i]));
            std::construct_at(&centers[i], boxes[i].center());
        }
    });
    const Bvh binary = builder == BvhBuilder::Median
                           ? build_median_bvh(boxes, centers)
                           : build_sah_bvh(boxes, centers, triangle_sah_config());
    triangle_count_ = n;
    bounds_ = binary.bounds();
    if (n != 0)
        tree_ = std::make_shared<const detail::WideBvh>(
            detail::collapse_to_wide(binary, triangles, boxes));
    set_simd_path(default_simd_path());
}

void TriangleBvh::set_simd_path(SimdPath path) {
    if (!simd_path_supported(path))
        throw Error(std::string("TriangleBvh: SIMD path ") + to_string(path) +
                    " is not supported here");
    const detail::WideKernels k = detail::wide_kernels(path);
    path_ = path;
    intersect_fn_ = k.intersect;
    occluded_fn_ = k.occluded;
}

PrimitiveHit TriangleBvh::intersect(const Ray& ray) const {
    if (!tree_) return {};
    return intersect_fn_(*tree_, ray);
}

PrimitiveHit TriangleBvh::intersect(const Ray& ray, glm::vec3& winding_normal) const {
    if (!tree_) return {};
    // Each path's entry point from a table made once: wide_kernels(path_) per query cost 38
    // instructions a ray (callgrind, librt_query_layers geometric).
    using Entry = PrimitiveHit (*)(const detail::WideBvh&, const Ray&, glm::vec3&);
    static_assert(static_cast<int>(SimdPath::Avx512) == 3, "one entry per SimdPath, in order");
    static const std::array<Entry, 4> kEntries = {
        detail::wide_kernels(SimdPath::Scalar).intersect_normal,
        detail::wide_kernels(SimdPath::Sse).intersect_normal,
        detail::wide_kernels(SimdPath::Avx2).intersect_normal,
        detail::wide_kernels(SimdPath::Avx512).intersect_normal};
    return kEntries[static_cast<std::size_t>(path_)](*tree_, ray, winding_normal);
}

bool TriangleBvh::occluded(const Ray& ray) const {
    if (!tree_) return false;
    return occluded_fn_(*tree_, ray);
}

namespace {

/// Refuses a stream whose output span does not match its rays.
void check_stream_sizes(const char* query, std::size_t rays, const char* out_name,
                        std::size_t out) {
    if (rays != out)
        throw Error(std::string("TriangleBvh::") + query + ": " + std::to_string(rays) +
                    " rays but " + std::to_string(out) + " " + out_name);
}

/// Trees of fewer bytes than this answer a stream ray by ray: the interleaved walk
/// (wide_stream.h) pays off only when its rays wait on memory. Measured (docs/benchmarks.md,
/// "Ray streams"), librt's stream over its single rays: 0.92 / 0.90 (incoherent / any hit)
/// on the 10k teapot (0.6 MB tree), 1.04 / 0.99 on the bunny (3.9 MB) and the 100k teapot
/// (5.6 MB), 1.17-1.18 / 1.14-1.16 on the dragon (48 MB) and the 1M teapot (56 MB).
constexpr std::size_t kStreamInterleaveBytes = std::size_t{8} << 20;

/// Rays of the stream compared with their neighbour by looks_coherent.
constexpr std::size_t kCoherenceSample = 16;

/// True when the stream's first rays each point within about a degree of the one before (a
/// camera's primary rays): those walk the same nodes one after the other, whose branches
/// then predict and whose nodes are in cache, so the interleaved walk only adds its
/// bookkeeping (docs/benchmarks.md, "Ray streams").
bool looks_coherent(std::span<const Ray> rays) {
    const std::size_t n = std::min(rays.size(), kCoherenceSample + 1);
    if (n < 2) return false;
    // cos(1 degree)^2: dot(a, b)^2 >= c |a|^2 |b|^2 with dot(a, b) > 0.
    constexpr float kCos2 = 0.99969541f;
    for (std::size_t i = 1; i < n; ++i) {
        const glm::vec3& a = rays[i - 1].direction;
        const glm::vec3& b = rays[i].direction;
        const float d = glm::dot(a, b);
        if (!(d > 0.0f && d * d >= kCos2 * glm::dot(a, a) * glm::dot(b, b))) return false;
    }
    return true;
}

/// Whether a stream takes the interleaved walk (wide_stream.h) rather than a loop of
/// single-ray queries: a tree beyond the caches and rays that are not coherent.
bool interleave_stream(const detail::WideBvh& tree, std::span<const Ray> rays) {
    return tree.memory_bytes() >= kStreamInterleaveBytes && rays.size() >= 2 &&
           !looks_coherent(rays);
}

}  // namespace

void TriangleBvh::intersect(std::span<const Ray> rays, std::span<PrimitiveHit> hits) const {
    check_stream_sizes("intersect", rays.size(), "hits", hits.size());
    if (!tree_) {
        std::fill(hits.begin(), hits.end(), PrimitiveHit{});
        return;
    }
    if (interleave_stream(*tree_, rays)) {
        detail::wide_kernels(path_).intersect_stream(*tree_, rays.data(), hits.data(), rays.size());
        return;
    }
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = intersect_fn_(*tree_, rays[i]);
}

void TriangleBvh::occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const {
    check_stream_sizes("occluded", rays.size(), "blocked flags", blocked.size());
    if (!tree_) {
        std::fill(blocked.begin(), blocked.end(), std::uint8_t{0});
        return;
    }
    if (interleave_stream(*tree_, rays)) {
        detail::wide_kernels(path_).occluded_stream(*tree_, rays.data(), blocked.data(),
                                                    rays.size());
        return;
    }
    for (std::size_t i = 0; i < rays.size(); ++i)
        blocked[i] = occluded_fn_(*tree_, rays[i]) ? 1 : 0;
}

BvhStats TriangleBvh::stats() const { return tree_ ? detail::wide_bvh_stats(*tree_) : BvhStats{}; }

TraversalCounts TriangleBvh::count_traversal(const Ray& ray, bool any_hit) const {
    return tree_ ? detail::count_wide_traversal(*tree_, ray, any_hit) : TraversalCounts{};
}

std::size_t TriangleBvh::memory_bytes() const { return tree_ ? tree_->memory_bytes() : 0; }

TriangleList::TriangleList(const TriangleMesh& mesh) {
    const MeshTriangles tris = mesh_triangles(mesh);
    triangles_.assign(tris.span().begin(), tris.span().end());
}

TriangleList::TriangleList(std::span<const Triangle> triangles)
    : triangles_(triangles.begin(), triangles.end()) {}

PrimitiveHit TriangleList::intersect(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle nearest{triangles_.data(), prepare_watertight(ray), {}};
    traverse_linear<false>(static_cast<std::uint32_t>(triangles_.size()), r, nearest);
    return nearest.hit;
}

bool TriangleList::occluded(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle any{triangles_.data(), prepare_watertight(ray), {}};
    return traverse_linear<true>(static_cast<std::uint32_t>(triangles_.size()), r, any);
}

}  // namespace librt
