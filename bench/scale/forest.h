#pragma once

// Issue 40 item 3's instanced scene: a "forest" of mesh prototypes (the Stanford dragon and
// bunny) at random, fixed-seed placements, and the glTF file that shows the same forest to
// rt_render. One layout serves the benchmark (librt's TopLevel against Embree's instances)
// and the render, so both see the same scene.

#include <librt/geometry/mesh.h>

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace librt::bench {

/// One placed copy of a prototype.
struct ForestPlacement {
    std::uint32_t prototype = 0;  ///< index into the prototypes
    glm::mat4 object_to_world{1.0f};
};

/// Moves and scales `mesh` so that it stands on y = 0, centred on the y axis, with a
/// bounding-box diagonal of 1 (the unit every placement is made in).
void stand_on_ground(TriangleMesh& mesh);

/// counts[p] copies of prototype p (meshes already stood on the ground), shuffled over the
/// cells of a square grid of side ceil(sqrt(total)) on the y = 0 plane, cells 1.2 units
/// apart; each copy turned about +y by a uniform angle, scaled uniformly in [0.7, 1.3] and
/// moved within its cell by up to a quarter cell. PCG32 from `seed`: the same counts and seed
/// give the same forest on every machine.
[[nodiscard]] std::vector<ForestPlacement> forest_placements(std::span<const std::uint32_t> counts,
                                                             std::uint64_t seed);

/// Triangles the placements put in the world: the sum of their prototypes' triangle counts.
[[nodiscard]] std::size_t placed_triangles(std::span<const TriangleMesh> prototypes,
                                           std::span<const ForestPlacement> placements);

/// The camera that looks down on a forest of `instances` placements: above its near (+z)
/// edge, looking at a point just past its centre, y up.
struct ForestCamera {
    glm::vec3 eye, target;
};
[[nodiscard]] ForestCamera forest_camera(std::size_t instances);

/// Writes `<dir>/<name>.gltf` and `<dir>/<name>.bin`: each prototype once as a glTF mesh
/// (positions and indices, a material of its own), a node per placement reusing it (its
/// matrix the placement's), a ground quad under the forest and forest_camera (4:3). Throws
/// librt::Error naming the file when it cannot be written.
void write_forest_gltf(const std::filesystem::path& dir, const std::string& name,
                       std::span<const TriangleMesh> prototypes,
                       std::span<const ForestPlacement> placements);

/// librt_scale_bench --check: a forest of two procedural prototypes written by
/// write_forest_gltf into a temporary directory and loaded back by load_scene_file must hold
/// the triangles, instances, prototypes and matrices the layout made. Prints what failed;
/// returns 0 when all held, else 1.
int check_forest_gltf();

}  // namespace librt::bench
