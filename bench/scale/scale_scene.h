#pragma once

// librt_scale_bench's scenes (the forest, the big teapot) and each engine's structure over
// them, with the build time and memory the benchmark reports.

#include "../embree_scene.h"
#include "forest.h"

#include <librt/accel/top_level.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>

#include <glm/geometric.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace librt::bench {

/// What one scene is: unique prototypes and how they are placed (a single mesh: one
/// prototype at identity, not instanced).
struct SceneData {
    std::string name;
    std::vector<TriangleMesh> prototypes;
    std::vector<ForestPlacement> placements;  ///< empty: the lone mesh as it is
    std::size_t unique = 0, placed = 0;
};

/// The forest: `dragons` dragons and `bunnies` bunnies from `data` (forest_placements, seed 40).
inline SceneData make_forest(const std::filesystem::path& data, std::uint32_t dragons,
                             std::uint32_t bunnies) {
    SceneData s;
    s.name = "forest";
    for (const char* file : {"stanford-dragon.obj", "stanford-bunny.obj"}) {
        const std::filesystem::path path = data / file;
        if (!std::filesystem::is_regular_file(path))
            throw Error(path.string() + ": not found (set LIBRT_DATA_DIR)");
        s.prototypes.push_back(load_obj(path));
        stand_on_ground(s.prototypes.back());
    }
    const std::uint32_t counts[] = {dragons, bunnies};
    s.placements = forest_placements(counts, 40);
    for (const TriangleMesh& m : s.prototypes) s.unique += m.triangle_count();
    s.placed = placed_triangles(s.prototypes, s.placements);
    return s;
}

/// The procedural teapot of about `triangles` triangles, as librt_bench's.
inline SceneData make_teapot(std::size_t triangles) {
    SceneData s;
    s.name = "teapot" + std::to_string(triangles / 1'000'000) + "M";
    TriangleMesh mesh = make_teapot_with_triangles(triangles);
    // Centred, bounding-box diagonal 100, as librt_bench's meshes.
    const BBox b = mesh.bounds();
    const float scale = 100.0f / glm::length(b.diagonal());
    transform(mesh, make_transform(glm::vec3(scale), glm::vec3(0.0f), -scale * b.center()));
    s.unique = s.placed = mesh.triangle_count();
    s.prototypes.push_back(std::move(mesh));
    return s;
}

/// librt's structure for a scene: a TriangleBvh for a lone mesh (as librt_bench), a
/// TopLevel of prototypes and instances for the forest.
class LibrtEngine {
public:
    explicit LibrtEngine(const SceneData& s) {
        if (s.placements.empty()) {
            bvh_ = TriangleBvh(s.prototypes[0]);
            return;
        }
        // Copying the meshes in is not the build; it happens before the clock starts.
        top_ = std::make_unique<TopLevel>();
        for (const TriangleMesh& m : s.prototypes) top_->add_prototype(m);
        const auto start = std::chrono::steady_clock::now();
        for (const ForestPlacement& p : s.placements)
            top_->add_instance(p.prototype, p.object_to_world);
        top_->build();
        seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    /// Builds and returns the build's wall seconds.
    static std::pair<std::unique_ptr<LibrtEngine>, double> build(const SceneData& s) {
        const auto start = std::chrono::steady_clock::now();
        auto e = std::make_unique<LibrtEngine>(s);
        const double total =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double seconds = e->top_ ? e->seconds_ : total;
        return {std::move(e), seconds};
    }
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const {
        if (!top_) return bvh_.intersect(ray);
        ObjectHit hit;
        return top_->intersect(ray, hit) ? hit.primitive : PrimitiveHit{};
    }
    [[nodiscard]] bool occluded(const Ray& ray) const {
        return top_ ? top_->occluded(ray) : bvh_.occluded(ray);
    }
    /// Acceleration-structure bytes: the TriangleBvh (nodes and leaf triangle blocks), or
    /// everything the TopLevel holds but its prototype meshes' arrays.
    [[nodiscard]] std::size_t accel_bytes() const {
        if (!top_) return bvh_.memory_bytes();
        std::size_t mesh = 0;
        for (std::uint32_t p = 0; p < top_->prototype_count(); ++p) {
            const TriangleMesh& m = top_->prototype_mesh(p);
            mesh += m.positions.capacity() * sizeof(glm::vec3) +
                    m.triangles.capacity() * sizeof(glm::uvec3) +
                    m.normals.capacity() * sizeof(glm::vec3);
        }
        return top_->memory_bytes() - mesh;
    }

private:
    TriangleBvh bvh_;
    std::unique_ptr<TopLevel> top_;
    double seconds_ = 0.0;
};

/// Embree's: one scene over the lone mesh, or prototype scenes under instances.
class EmbreeEngine {
public:
    EmbreeEngine(const SceneData& s, EmbreeQuality q) {
        if (s.placements.empty()) {
            single_ = std::make_unique<EmbreeScene>(s.prototypes[0], q);
            return;
        }
        std::vector<const TriangleMesh*> protos;
        for (const TriangleMesh& m : s.prototypes) protos.push_back(&m);
        std::vector<EmbreeInstance> inst;
        for (const ForestPlacement& p : s.placements)
            inst.push_back({p.prototype, p.object_to_world});
        instanced_ = std::make_unique<EmbreeInstancedScene>(protos, inst, q);
    }
    [[nodiscard]] PrimitiveHit intersect(const Ray& r) const {
        return single_ ? single_->intersect(r) : instanced_->intersect(r);
    }
    [[nodiscard]] bool occluded(const Ray& r) const {
        return single_ ? single_->occluded(r) : instanced_->occluded(r);
    }
    [[nodiscard]] std::size_t accel_bytes() const {
        return single_ ? single_->memory_bytes() : instanced_->memory_bytes();
    }
    [[nodiscard]] double build_seconds() const {
        return single_ ? single_->build_seconds() : instanced_->build_seconds();
    }

private:
    std::unique_ptr<EmbreeScene> single_;
    std::unique_ptr<EmbreeInstancedScene> instanced_;
};

}  // namespace librt::bench
