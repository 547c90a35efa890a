#pragma once

// Embree 3 behind librt's engine interface, so the benchmark can trace the same
// meshes and rays through both. Compiled only when CMake found Embree
// (LIBRT_HAVE_EMBREE); embree_available() says whether it was.

#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>

#include <cstddef>
#include <memory>

namespace librt::bench {

/// True when the benchmark was built against Embree.
[[nodiscard]] bool embree_available();

/// One Embree scene holding one triangle mesh: default build quality, no scene
/// flags, on a device shared by all scenes (created on first use).
class EmbreeScene {
public:
    /// Builds the scene (rtcCommitScene) over the mesh's positions and triangles.
    explicit EmbreeScene(const TriangleMesh& mesh);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Nearest hit through rtcIntersect1 (t, u, v and the mesh's triangle index).
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// Any hit through rtcOccluded1.
    [[nodiscard]] bool occluded(const Ray& ray) const;
    /// Bytes Embree allocated while committing the scene and still holds (its BVH and
    /// leaf data), as counted by the device's memory monitor; the mesh's vertex and
    /// index arrays are shared with Embree, so they are not counted.
    [[nodiscard]] std::size_t memory_bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace librt::bench
