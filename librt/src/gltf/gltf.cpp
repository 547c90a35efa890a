// load_gltf: reads the file, checks the container and the JSON (with paths), lets
// tinygltf parse, then reads materials, the node graph and meshes, and decodes images.

#include "gltf/gltf_internal.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/gltf/gltf.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
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

namespace {

using namespace gltf_detail;

/// Memory set aside while a glTF loads. Some destructors allocate: nlohmann::json's (in
/// tinygltf, and librt's own tree) builds a stack to free a large tree, inside a noexcept
/// destructor, so an allocation that fails while the stack unwinds from std::bad_alloc
/// would abort the program. The first failed allocation therefore frees this reserve and
/// throws (std::set_new_handler), and unwinding finds the memory it needs. One load at a
/// time holds a reserve (the handler is process-wide); a load that starts while another
/// holds one goes without.
class AllocationReserve {
public:
    explicit AllocationReserve(std::size_t bytes) {
        void* expected = nullptr;
        void* block = ::operator new(bytes, std::nothrow);
        if (block == nullptr) throw std::bad_alloc();
        if (!reserve_.compare_exchange_strong(expected, block)) {
            ::operator delete(block);
            return;
        }
        owner_ = true;
        previous_ = std::set_new_handler(&release_and_fail);
    }
    ~AllocationReserve() {
        if (!owner_) return;
        std::set_new_handler(previous_);
        ::operator delete(reserve_.exchange(nullptr));
    }
    AllocationReserve(const AllocationReserve&) = delete;
    AllocationReserve& operator=(const AllocationReserve&) = delete;

private:
    static void release_and_fail() {
        // Freed once; any failure throws, so the allocation is never retried in a loop.
        ::operator delete(reserve_.exchange(nullptr));
        throw std::bad_alloc();
    }
    static inline std::atomic<void*> reserve_{nullptr};
    bool owner_ = false;
    std::new_handler previous_ = nullptr;
};

/// The reserve for a file of `bytes`: its trees take a few times the JSON, and freeing one
/// takes a stack of 16 bytes per element of its largest container.
std::size_t reserve_bytes(std::uint64_t bytes) {
    return std::size_t(
        std::clamp<std::uint64_t>(8 * bytes, std::uint64_t{16} << 20u, std::uint64_t{1} << 30u));
}

/// The memory bound of a load that has read `read` bytes of files.
std::uint64_t memory_bound(const GltfLoadOptions& options, std::uint64_t read) {
    if (options.max_memory_bytes != 0) return options.max_memory_bytes;
    return kMemoryPerByteRead * read + kMemoryBaseline;
}

void load(const std::filesystem::path& path, const GltfLoadOptions& options, Context& ctx,
          GltfScene& scene) {
    const std::string bytes = read_regular_file(path, options.max_file_bytes);
    // Each file's digest is taken from the bytes in memory, never by a second read.
    scene.files_read.push_back({path, digest_of(bytes)});
    const AllocationReserve reserve(reserve_bytes(bytes.size()));
    const Container container = split_container(bytes, ctx);
    LoadLimits limits;
    limits.max_file_bytes = options.max_file_bytes;
    limits.allow_outside_files = options.allow_outside_files;
    limits.grow_with_reads = options.max_memory_bytes == 0;
    // The JSON's tree is built before external files are known: it gets what the file alone
    // allows, less the file itself.
    const std::uint64_t own_bound = memory_bound(options, bytes.size());
    if (own_bound <= bytes.size())
        ctx.fail("", "max_memory_bytes " + std::to_string(own_bound) +
                         " is less than the file's own size");
    limits.memory = own_bound - bytes.size();
    const std::string base_dir = path.parent_path().string();
    JsonFacts facts = check_json(container, base_dir, limits, ctx);
    // tinygltf takes lengths as unsigned int.
    if (facts.tinygltf_json.size() > std::numeric_limits<unsigned int>::max())
        ctx.fail("", "JSON of more than 4 GiB");

    // Every distinct external buffer file is read once, and only if the whole parse fits.
    const std::uint64_t files = bytes.size() + facts.external_bytes;
    const std::uint64_t bound = memory_bound(options, files);
    if (files + facts.tinygltf_bytes > bound) {
        ctx.fail("", "loading would take about " + std::to_string(files + facts.tinygltf_bytes) +
                         " bytes, more than the " + std::to_string(bound) +
                         " this file may use (16 times the bytes read plus 256 MiB; "
                         "GltfLoadOptions::max_memory_bytes sets another bound)");
    }
    std::map<std::string, std::string> file_bytes;
    std::vector<std::string_view> buffers;
    for (const BufferSource& b : facts.buffers) {
        switch (b.kind) {
            case BufferSource::Kind::Bin:
                buffers.push_back(container.bin);
                break;
            case BufferSource::Kind::Data:
                buffers.emplace_back(reinterpret_cast<const char*>(b.data.data()), b.data.size());
                break;
            case BufferSource::Kind::File: {
                auto it = file_bytes.find(b.file);
                if (it == file_bytes.end()) {
                    it = file_bytes
                             .emplace(b.file, read_regular_file(b.file, options.max_file_bytes))
                             .first;
                    scene.files_read.push_back({b.file, digest_of(it->second)});
                }
                // The pre-pass checked the size; a file that shrank since is caught here.
                if (it->second.size() < b.byte_length)
                    ctx.fail("buffers", quote_untrusted(b.file) + " shrank while being read");
                buffers.push_back(it->second);
                break;
            }
        }
    }
    ctx.set_buffers(std::move(buffers));

    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(no_file_access());
    loader.SetImageLoader(&ignore_image, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        ok = loader.LoadASCIIFromString(&model, &err, &warn, facts.tinygltf_json.data(),
                                        static_cast<unsigned int>(facts.tinygltf_json.size()),
                                        base_dir);
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
    // tinygltf's warnings are about the image stand-ins: decode_images reports images.
    std::string().swap(facts.tinygltf_json);
    // Decoded output may take what the bound leaves beside the files and the Model:
    // geometry expands (u8 indices to 12-byte triangles, quantised attributes to floats)
    // and images decompress, but never past the bound.
    const std::uint64_t held = files + facts.model_bytes;
    ctx.set_budget(bound > held ? bound - held : 0);

    decode_meshopt_views(model, ctx);
    read_materials(model, facts.images, ctx, scene);
    read_nodes(model, options.scene, ctx, scene);
    const int variant = read_variants(model, options.variant, ctx, scene);
    read_meshes(model, variant, ctx, scene);
    if (options.decode_images) decode_images(model, facts.images, limits, ctx, scene);
}

}  // namespace

GltfScene load_gltf(const std::filesystem::path& path, const GltfLoadOptions& options) {
    if (options.scene < -1)
        throw Error("GltfLoadOptions::scene = " + std::to_string(options.scene) +
                    ": must be >= -1");
    GltfScene scene;
    Context ctx(path.string(), &scene.warnings);
    try {
        load(path, options, ctx, scene);
        return scene;
    } catch (const std::bad_alloc&) {
        // Allocation failure anywhere in loading (a memory limit below the bound) is an
        // error like any other, never an abort.
        scene = GltfScene{};
        ctx.fail("", "out of memory while loading (allocation failed)");
    }
}

}  // namespace librt
