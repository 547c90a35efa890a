// Instancing: 64 instances of one dragon prototype against one dragon, built and measured in
// the same row so both see the same machine load.
//
// Row dragon/instanced64_vs_single: each iteration builds a TopLevel holding one dragon mesh
// and one holding one dragon prototype placed by 64 transforms (alternating which goes
// first), timing each build (the prototype's BVH and the top level; copying the mesh in is
// not timed). Counters: single_ms, instanced_ms, build_ratio (instanced / single);
// bvh_MB (one dragon's TriangleBvh), single_MB and instanced_MB (all a TopLevel holds:
// meshes, BVHs, instances, top structure), memory_ratio (instanced / single) and
// accel_ratio ((instanced_MB - the mesh arrays) / bvh_MB: what 64 instances cost against
// one dragon's BVH).
//
// Run: ./build/release/bench/librt_instancing_bench [--benchmark_repetitions=5]

#include <librt/accel/top_level.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/obj/obj.h>

#include <benchmark/benchmark.h>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

namespace {

using namespace librt;
namespace fs = std::filesystem;

constexpr int kInstances = 64;

fs::path data_dir() {
    if (const char* env = std::getenv("LIBRT_DATA_DIR"); env && *env) return env;
    return LIBRT_DEFAULT_DATA_DIR;
}

/// 64 placements on a 4 x 4 x 4 grid, each rotated and scaled differently.
std::vector<glm::mat4> placements(const BBox& box) {
    std::vector<glm::mat4> out;
    const float spacing = 2.5f * glm::length(box.diagonal());
    for (int k = 0; k < kInstances; ++k) {
        const glm::vec3 cell(float(k % 4), float((k / 4) % 4), float(k / 16));
        glm::mat4 m = glm::translate(glm::mat4(1.0f), spacing * cell);
        m = glm::rotate(m, 0.1f * float(k), glm::normalize(glm::vec3(1.0f, float(k % 3), 2.0f)));
        m = glm::scale(m, glm::vec3(1.0f + 0.01f * float(k)));
        out.push_back(m);
    }
    return out;
}

std::size_t mesh_bytes(const TriangleMesh& m) {
    return m.positions.capacity() * sizeof(glm::vec3) +
           m.triangles.capacity() * sizeof(glm::uvec3) + m.normals.capacity() * sizeof(glm::vec3) +
           m.uvs.capacity() * sizeof(glm::vec2) + m.material_ids.capacity() * sizeof(std::uint32_t);
}

void instanced_vs_single(benchmark::State& state, const TriangleMesh& dragon) {
    const std::vector<glm::mat4> transforms = placements(dragon.bounds());
    using Clock = std::chrono::steady_clock;
    double single_s = 0.0, instanced_s = 0.0;
    std::size_t single_bytes = 0, instanced_bytes = 0, proto_mesh_bytes = 0;
    bool instanced_first = false;
    for (auto _ : state) {
        // Copies made outside the timed part: the build is what is measured.
        TriangleMesh copy_single = dragon, copy_instanced = dragon;
        TopLevel single, instanced;
        const auto build_single = [&] {
            const auto t0 = Clock::now();
            single.add_mesh(single.add_prototype(std::move(copy_single)));
            single.build();
            single_s += std::chrono::duration<double>(Clock::now() - t0).count();
        };
        const auto build_instanced = [&] {
            const auto t0 = Clock::now();
            const std::uint32_t proto = instanced.add_prototype(std::move(copy_instanced));
            for (const glm::mat4& m : transforms) instanced.add_instance(proto, m);
            instanced.build();
            instanced_s += std::chrono::duration<double>(Clock::now() - t0).count();
        };
        if (instanced_first) {
            build_instanced();
            build_single();
        } else {
            build_single();
            build_instanced();
        }
        instanced_first = !instanced_first;
        single_bytes = single.memory_bytes();
        instanced_bytes = instanced.memory_bytes();
        proto_mesh_bytes = mesh_bytes(instanced.prototype_mesh(0));
        benchmark::DoNotOptimize(single_bytes + instanced_bytes);
    }
    const double n = double(state.iterations());
    const double bvh_bytes = double(TriangleBvh(dragon).memory_bytes());
    state.counters["single_ms"] = 1e3 * single_s / n;
    state.counters["instanced_ms"] = 1e3 * instanced_s / n;
    state.counters["build_ratio"] = instanced_s / single_s;
    state.counters["bvh_MB"] = bvh_bytes * 1e-6;
    state.counters["single_MB"] = double(single_bytes) * 1e-6;
    state.counters["instanced_MB"] = double(instanced_bytes) * 1e-6;
    state.counters["memory_ratio"] = double(instanced_bytes) / double(single_bytes);
    state.counters["accel_ratio"] = double(instanced_bytes - proto_mesh_bytes) / bvh_bytes;
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    const fs::path path = data_dir() / "stanford-dragon.obj";
    if (!fs::is_regular_file(path)) {
        std::cerr << "librt_instancing_bench: " << path << " not found (set LIBRT_DATA_DIR)\n";
        return 1;
    }
    const TriangleMesh dragon = load_obj(path);
    benchmark::RegisterBenchmark("dragon/instanced64_vs_single",
                                 [&](benchmark::State& s) { instanced_vs_single(s, dragon); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(5);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
