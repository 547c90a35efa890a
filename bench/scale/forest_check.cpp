// librt_scale_bench --check: the forest's glTF, written and loaded back (a ctest).

#include "forest.h"

#include <librt/accel/top_level.h>
#include <librt/geometry/procedural.h>
#include <librt/loader/scene_file.h>

#include <glm/geometric.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

namespace librt::bench {

namespace fs = std::filesystem;

int check_forest_gltf() {
    std::vector<TriangleMesh> protos;
    for (const std::size_t n : {2'000u, 500u}) {
        protos.push_back(make_teapot_with_triangles(n));
        stand_on_ground(protos.back());
    }
    const std::uint32_t counts[] = {3, 4};
    const auto placements = forest_placements(counts, 7);
    const fs::path dir =
        fs::temp_directory_path() / ("librt_scale_check_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    int failures = 0;
    auto expect = [&](bool ok, const std::string& what) {
        if (!ok) {
            std::printf("FAILED: %s\n", what.c_str());
            ++failures;
        }
    };
    try {
        write_forest_gltf(dir, "forest", protos, placements);
        LoadedScene loaded = load_scene_file(dir / "forest.gltf");
        const std::size_t placed = placed_triangles(protos, placements);
        const std::size_t stored =
            protos[0].triangle_count() + protos[1].triangle_count() + 2;  // + the ground quad
        expect(placements.size() == 7, "7 placements, got " + std::to_string(placements.size()));
        expect(loaded.triangles_placed == placed + 2,
               "triangles placed " + std::to_string(loaded.triangles_placed) + ", expected " +
                   std::to_string(placed + 2));
        expect(loaded.triangles_stored == stored, "triangles stored " +
                                                      std::to_string(loaded.triangles_stored) +
                                                      ", expected " + std::to_string(stored));
        const TopLevel& top = loaded.scene.top_level();
        expect(top.instance_count() == placements.size(),
               "instances " + std::to_string(top.instance_count()));
        for (std::size_t i = 0; i < std::min(top.instance_count(), placements.size()); ++i) {
            const std::uint32_t object = top.instance_object(std::uint32_t(i));
            const std::size_t tris = top.prototype_mesh(top.prototype_of(object)).triangle_count();
            expect(tris == protos[placements[i].prototype].triangle_count(),
                   "instance " + std::to_string(i) + " shows a prototype of " +
                       std::to_string(tris) + " triangles");
            const auto [linear, shift] = top.object_to_world(object);
            const glm::mat4& m = placements[i].object_to_world;
            float err = 0.0f;
            for (int c = 0; c < 3; ++c) {
                err = std::max(err, glm::length(linear[c] - glm::vec3(m[c])));
            }
            err = std::max(err, glm::length(shift - glm::vec3(m[3])));
            // The file holds each entry to 9 digits: a float's own rounding, relative 2^-24
            // of entries of at most a few units.
            expect(err < 1e-5f,
                   "instance " + std::to_string(i) + " matrix differs by " + std::to_string(err));
        }
    } catch (const std::exception& e) {
        expect(false, e.what());
    }
    fs::remove_all(dir);
    std::printf("scale forest glTF check: %s\n", failures ? "FAILED" : "passed");
    return failures ? 1 : 0;
}

}  // namespace librt::bench
