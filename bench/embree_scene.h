#pragma once

// Embree 3 behind librt's engine interface, so the benchmark can trace the same
// meshes and rays through both. Compiled only when CMake found Embree
// (LIBRT_HAVE_EMBREE); embree_available() says whether it was.

#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace librt::bench {

/// True when the benchmark was built against Embree.
[[nodiscard]] bool embree_available();

/// Embree's build quality (rtcSetSceneBuildQuality): Default is what an application gets
/// without asking (RTC_BUILD_QUALITY_MEDIUM, binned SAH); High is RTC_BUILD_QUALITY_HIGH
/// (spatial splits for static scenes), Embree's best tree at a slower build. Robust is the
/// default quality with RTC_SCENE_FLAG_ROBUST: Embree's robust traversal and its Pluecker
/// triangle test on the vertices (no hole along shared edges), the robustness of librt's
/// watertight test.
enum class EmbreeQuality { Default, High, Robust };

/// One Embree scene holding one triangle mesh: no scene flags (but for Robust), on a device shared
/// by all scenes (created on first use).
class EmbreeScene {
public:
    /// Builds the scene (rtcCommitScene) over the mesh's positions and triangles.
    explicit EmbreeScene(const TriangleMesh& mesh, EmbreeQuality quality = EmbreeQuality::Default);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Nearest hit through rtcIntersect1 (t, u, v and the mesh's triangle index).
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// Any hit through rtcOccluded1.
    [[nodiscard]] bool occluded(const Ray& ray) const;
    /// Closest hits of a stream through rtcIntersect1M (one call for all the rays, their
    /// RTCRayHit records in an array; the copy from and back to librt's types is part of
    /// the call, as it is of intersect(ray)), the context's flags
    /// RTC_INTERSECT_CONTEXT_FLAG_COHERENT when `coherent`, else _INCOHERENT. Returns the
    /// number of hits; hits.size() must equal rays.size().
    std::size_t intersect_stream(std::span<const Ray> rays, std::span<PrimitiveHit> hits,
                                 bool coherent) const;
    /// Any hits of a stream through rtcOccluded1M (as intersect_stream): blocked[i] is 1 when
    /// rays[i] is occluded. Returns the number occluded.
    std::size_t occluded_stream(std::span<const Ray> rays, std::span<std::uint8_t> blocked,
                                bool coherent) const;
    /// Bytes Embree allocated while committing the scene and still holds (its BVH and
    /// leaf data), as counted by the device's memory monitor; the mesh's vertex and
    /// index arrays are shared with Embree, so they are not counted.
    [[nodiscard]] std::size_t memory_bytes() const;
    /// Wall seconds of the build (rtcNewScene to rtcCommitScene), without the copy of the
    /// mesh's arrays into Embree's layout.
    [[nodiscard]] double build_seconds() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// A prototype placed by an affine object-to-world matrix (as TopLevel::add_instance).
struct EmbreeInstance {
    std::uint32_t prototype;  ///< index into the prototype meshes
    glm::mat4 object_to_world;
};

/// Embree's two-level scene: each prototype mesh in a scene of its own (built once), placed
/// by RTC_GEOMETRY_TYPE_INSTANCE geometries in a top scene; the same build quality for all.
class EmbreeInstancedScene {
public:
    /// Builds the prototype scenes and the top scene. The meshes must outlive this object
    /// only during construction (their arrays are copied).
    EmbreeInstancedScene(std::span<const TriangleMesh* const> prototypes,
                         std::span<const EmbreeInstance> instances,
                         EmbreeQuality quality = EmbreeQuality::Default);
    ~EmbreeInstancedScene();
    EmbreeInstancedScene(const EmbreeInstancedScene&) = delete;
    EmbreeInstancedScene& operator=(const EmbreeInstancedScene&) = delete;

    /// Nearest hit (t, u, v and the prototype's triangle index).
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const;
    /// Any hit.
    [[nodiscard]] bool occluded(const Ray& ray) const;
    /// Bytes the device allocated while committing all the scenes and still holds (BVHs,
    /// leaf data, instance records); the vertex and index arrays are shared, not counted.
    [[nodiscard]] std::size_t memory_bytes() const;
    /// Bytes of the shared vertex (12 per vertex) and index (12 per triangle) arrays.
    [[nodiscard]] std::size_t shared_array_bytes() const;
    /// Wall seconds of the builds (the prototypes' scenes and the top scene), without the
    /// copy of the meshes' arrays.
    [[nodiscard]] double build_seconds() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace librt::bench
