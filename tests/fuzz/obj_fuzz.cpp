// libFuzzer target: arbitrary bytes as an OBJ file -> load_obj -> BVH build -> a few rays.
// Any outcome but a clean mesh or a librt::Error is a bug (crash, hang, sanitizer report).
// Run: ./build/fuzz/tests/fuzz/obj_fuzz -max_total_time=60 tests/fuzz/corpus/obj

#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>
#include <librt/obj/obj.h>

#include <glm/geometric.hpp>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

std::filesystem::path scratch_file() {
    // One file per process, reused: load_obj reads from a path.
    static const std::filesystem::path path =
        std::filesystem::temp_directory_path() /
        ("librt_obj_fuzz_" + std::to_string(::getpid()) + ".obj");
    return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = scratch_file();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    std::vector<std::string> warnings;
    librt::ObjLoadOptions options;
    options.warnings = &warnings;
    try {
        const librt::TriangleMesh mesh = librt::load_obj(path, options);
        librt::validate(mesh);
        for (const librt::BvhBuilder builder :
             {librt::BvhBuilder::Median, librt::BvhBuilder::Sah}) {
            const librt::TriangleBvh bvh(mesh, builder);
            const librt::BBox box = bvh.bounds();
            if (box.empty()) continue;
            // A ray from outside through the box centre, and one along each axis.
            for (const glm::vec3 dir :
                 {glm::vec3(1, 1, 1), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)}) {
                librt::Ray ray;
                ray.direction = dir;
                ray.origin = box.center() - dir * (glm::length(box.diagonal()) + 1.0f);
                const librt::PrimitiveHit hit = bvh.intersect(ray);
                if (hit.valid() && hit.primitive_id >= mesh.triangle_count()) __builtin_trap();
                if (hit.valid() != bvh.occluded(ray)) __builtin_trap();
            }
        }
    } catch (const librt::Error&) {
        // Rejected with a message: the expected outcome for bad input.
    }
    return 0;
}
