// libFuzzer target: arbitrary bytes as a glTF file (.glb or .gltf, told apart by content)
// -> load_gltf -> consistency of what it returns -> the Scene built from it, committed, and
// a few pixels rendered, so what the loader passes on is fuzzed too. Any outcome but a
// consistent GltfScene, printable warnings and finite pixels, or a librt::Error, is a bug (crash,
// hang, sanitizer report, huge allocation). Run: ./build/fuzz/tests/fuzz/gltf_fuzz
// -max_total_time=60 tests/fuzz/corpus/gltf

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/integrator/integrators.h>
#include <librt/render/renderer.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

std::filesystem::path scratch_file() {
    // One directory per process (relative URIs in an input resolve inside it), one file
    // reused: load_gltf reads from a path.
    static const std::filesystem::path path = [] {
        const auto dir = std::filesystem::temp_directory_path() /
                         ("librt_gltf_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        return dir / "input.glb";
    }();
    return path;
}

void check(bool ok) {
    if (!ok) __builtin_trap();
}

/// Every warning is one printable line (docs/robustness.md, "Its strings reach messages
/// escaped and short"): no control character a file could put there survives.
void check_printable(const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings)
        for (const char c : w) check(static_cast<unsigned char>(c) >= 0x20 && c != 0x7f);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = scratch_file();
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    librt::GltfLoadOptions options;
    options.max_file_bytes = 1u << 20u;
    try {
        const librt::GltfScene scene = librt::load_gltf(path, options);
        for (const librt::GltfMesh& mesh : scene.meshes) {
            for (const librt::GltfPrimitive& p : mesh.primitives) {
                const std::size_t n = p.positions.size();
                for (const glm::uvec3& t : p.triangles) check(t.x < n && t.y < n && t.z < n);
                for (const std::size_t m : {p.normals.size(), p.tangents.size(), p.uv0.size(),
                                            p.uv1.size(), p.colors.size()})
                    check(m == 0 || m == n);
                check(p.material < int(scene.materials.size()));
            }
        }
        for (const librt::GltfInstance& i : scene.instances)
            check(i.mesh >= 0 && std::size_t(i.mesh) < scene.meshes.size());
        for (const librt::GltfTexture& t : scene.textures) {
            if (t.image < 0) continue;
            check(std::size_t(t.image) < scene.images.size());
            const librt::GltfImage& img = scene.images[std::size_t(t.image)];
            check(img.rgba.size() == std::size_t(img.width) * std::size_t(img.height) * 4);
        }
        (void)scene.triangles_placed();
        check_printable(scene.warnings);
        // What the loader passed on, built, committed and rendered (4 x 4, 1 sample).
        librt::SceneFileOptions file_options;
        file_options.width = file_options.height = 4;
        librt::LoadedScene loaded = librt::scene_from_gltf(scene, file_options);
        check_printable(loaded.warnings);
        loaded.scene.commit();
        librt::PathTracer path_tracer;
        librt::RenderSettings settings;
        settings.threads = 1;
        const librt::Image image =
            librt::render(loaded.scene, librt::Camera(loaded.camera), path_tracer, settings);
        for (const glm::vec3& p : image.pixels)
            check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    } catch (const librt::Error&) {
        // Rejected with a message: the expected outcome for bad input.
    }
    return 0;
}
