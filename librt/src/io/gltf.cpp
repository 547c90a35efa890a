// load_gltf: reads the file, checks the container and the JSON (with paths), lets
// tinygltf parse, then reads materials, the node graph and meshes, and decodes images.

#include "io/gltf_internal.h"

#include <librt/core/error.h>
#include <librt/io/gltf.h>

#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <string>

namespace librt {

glm::mat3 GltfTextureTransform::matrix() const {
    // KHR_texture_transform: T(offset) * R(rotation) * S(scale), with R written row-major
    // in the extension as [cos sin 0; -sin cos 0; 0 0 1]. glm indexes [column][row].
    const float c = std::cos(rotation), s = std::sin(rotation);
    glm::mat3 t(1.0f), r(1.0f), sc(1.0f);
    t[2][0] = offset.x;
    t[2][1] = offset.y;
    r[0][0] = c;
    r[1][0] = s;
    r[0][1] = -s;
    r[1][1] = c;
    sc[0][0] = scale.x;
    sc[1][1] = scale.y;
    return t * r * sc;
}

std::size_t GltfScene::triangles_stored() const {
    std::size_t n = 0;
    for (const GltfMesh& m : meshes) n += m.triangle_count();
    return n;
}

std::size_t GltfScene::triangles_placed() const {
    std::size_t n = 0;
    for (const GltfInstance& i : instances) n += meshes[std::size_t(i.mesh)].triangle_count();
    return n;
}

GltfScene load_gltf(const std::filesystem::path& path, const GltfLoadOptions& options) {
    using namespace gltf_detail;
    if (options.scene < -1)
        throw Error("GltfLoadOptions::scene = " + std::to_string(options.scene) +
                    ": must be >= -1");
    GltfScene scene;
    Context ctx(path.string(), &scene.warnings);
    const std::string bytes = read_regular_file(path, options.max_file_bytes);
    const Container container = split_container(bytes, ctx);
    // tinygltf takes lengths as unsigned int.
    if (container.json.size() > std::numeric_limits<unsigned int>::max())
        ctx.fail("", "JSON of more than 4 GiB");
    FsRouting routing;
    routing.base_dir = path.parent_path().string();
    routing.max_bytes = options.max_file_bytes;
    const JsonFacts facts = check_json(container, routing.base_dir, options.max_file_bytes, ctx);
    routing.truncate_to = facts.buffer_files;
    // Decoded output may be this large: geometry expands (u8 indices to 12-byte triangles,
    // quantised attributes to floats) and images decompress, but never without bound.
    const std::uint64_t read = bytes.size() + facts.external_bytes;
    ctx.set_budget(64 * read + (std::uint64_t{256} << 20u));

    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(routing.callbacks());
    loader.SetImageLoader(&keep_encoded_image, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        if (container.binary) {
            // The declared length: at most the file's size (split_container), so < 2^32.
            const auto length = static_cast<unsigned int>(container.length);
            ok = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                             length, routing.base_dir);
        } else {
            ok = loader.LoadASCIIFromString(&model, &err, &warn, container.json.data(),
                                            static_cast<unsigned int>(container.json.size()),
                                            routing.base_dir);
        }
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        // tinygltf reports through err; an exception from inside it is still bad input.
        ctx.fail("", std::string("invalid glTF: ") + e.what());
    }
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        for (char& c : err)
            if (c == '\n') c = ';';
        ctx.fail("", "invalid glTF: " + (err.empty() ? std::string("(no reason given)") : err));
    }
    // tinygltf's warnings are about images it could not read: decode_images reports those.

    read_materials(model, ctx, scene);
    read_nodes(model, options.scene, ctx, scene);
    read_meshes(model, ctx, scene);
    if (options.decode_images) decode_images(model, routing.failures, ctx, scene);
    return scene;
}

}  // namespace librt
