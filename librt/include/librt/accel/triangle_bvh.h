#pragma once

#include <librt/accel/bvh.h>
#include <librt/accel/bvh_builder.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/geometry/triangle.h>

#include <cstdint>
#include <vector>

namespace librt {

/// Closest-hit and any-hit queries over a triangle mesh through a BVH. The triangles
/// are copied in leaf order, so a leaf reads contiguous memory; hits report the
/// mesh's own triangle index.
class TriangleBvh {
public:
    TriangleBvh() = default;
    /// Builds over all triangles of the mesh. Throws librt::Error for an index out of
    /// range or a non-finite position.
    explicit TriangleBvh(const TriangleMesh& mesh, BvhBuilder builder = BvhBuilder::Sah);
    /// Builds over loose triangles (primitive id = index in the span).
    explicit TriangleBvh(std::span<const Triangle> triangles, BvhBuilder builder = BvhBuilder::Sah);

    /// Nearest hit with t in (ray.t_min, ray.t_max), if any.
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// True when anything lies in (ray.t_min, ray.t_max): for shadow rays.
    [[nodiscard]] bool occluded(const Ray& ray) const;

    [[nodiscard]] const Bvh& bvh() const { return bvh_; }
    [[nodiscard]] BBox bounds() const { return bvh_.bounds(); }
    [[nodiscard]] std::size_t triangle_count() const { return triangles_.size(); }
    /// Bytes of the BVH plus its leaf-ordered triangle copy.
    [[nodiscard]] std::size_t memory_bytes() const;

private:
    void build(std::span<const Triangle> triangles, BvhBuilder builder);

    Bvh bvh_;
    std::vector<Triangle> triangles_;  ///< in slot order
};

/// The naive alternative with the same interface: tests every triangle for every ray.
/// Kept for tests (ground truth) and benchmarks (the thing a BVH must beat).
class TriangleList {
public:
    TriangleList() = default;
    explicit TriangleList(const TriangleMesh& mesh);
    explicit TriangleList(std::span<const Triangle> triangles);

    /// Nearest hit with t in (ray.t_min, ray.t_max), if any.
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// True when anything lies in (ray.t_min, ray.t_max).
    [[nodiscard]] bool occluded(const Ray& ray) const;
    [[nodiscard]] std::size_t triangle_count() const { return triangles_.size(); }

private:
    std::vector<Triangle> triangles_;
};

}  // namespace librt
