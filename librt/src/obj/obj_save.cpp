// save_obj: a mesh written as OBJ (and its materials as MTL), each file atomically.

#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/obj/obj.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

namespace librt {

namespace {

namespace fs = std::filesystem;

/// Appends text and numbers to a buffer flushed to a stream in large blocks.
class Writer {
public:
    explicit Writer(detail::AtomicFile& out) : out_(out) { buffer_.reserve(kBlock + 256); }
    ~Writer() = default;
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    Writer& operator<<(std::string_view s) {
        buffer_.append(s);
        if (buffer_.size() >= kBlock) flush();
        return *this;
    }
    Writer& operator<<(char c) {
        buffer_.push_back(c);
        return *this;
    }
    /// Shortest decimal that reads back as the same float.
    Writer& operator<<(float x) { return put(x); }
    Writer& operator<<(std::uint64_t x) { return put(x); }
    Writer& operator<<(int x) { return put(x); }
    void flush() {
        out_.write(buffer_);
        buffer_.clear();
    }

private:
    static constexpr std::size_t kBlock = std::size_t{1} << 20;

    template <class T>
    Writer& put(T x) {
        char tmp[32];
        const auto result = std::to_chars(tmp, tmp + sizeof(tmp), x);
        return *this << std::string_view(tmp, static_cast<std::size_t>(result.ptr - tmp));
    }

    detail::AtomicFile& out_;
    std::string buffer_;
};

/// Runs body on the library's one atomic writer (io/file_io.h): readers see the old file
/// or the complete new one, and a kill during the write leaves no temporary.
void write_atomically(const fs::path& path, const std::function<void(Writer&)>& body) {
    detail::AtomicFile file(path);
    Writer w(file);
    body(w);
    w.flush();
    file.commit();
}

std::string material_name(const TriangleMesh& mesh, std::size_t i) {
    const std::string& name = mesh.materials[i].name;
    return name.empty() ? "material_" + std::to_string(i) : name;
}

void write_mtl(const TriangleMesh& mesh, const fs::path& path) {
    const fs::path dir = fs::absolute(path).parent_path();
    write_atomically(path, [&](Writer& w) {
        w << "# written by librt save_obj\n";
        auto rgb = [&](std::string_view key, const glm::vec3& c) {
            w << key << ' ' << c.x << ' ' << c.y << ' ' << c.z << '\n';
        };
        for (std::size_t i = 0; i < mesh.materials.size(); ++i) {
            const MeshMaterial& m = mesh.materials[i];
            w << "newmtl " << material_name(mesh, i) << '\n';
            rgb("Kd", m.diffuse);
            rgb("Ks", m.specular);
            rgb("Ke", m.emission);
            w << "Ni " << m.ior << "\nd " << m.dissolve << "\nillum " << m.illum << '\n';
            if (!m.diffuse_texture.empty()) {
                // The texture is stored relative to the working directory; MTL wants it
                // relative to the MTL's own directory.
                const fs::path tex = fs::absolute(m.diffuse_texture).lexically_proximate(dir);
                w << "map_Kd " << tex.generic_string() << '\n';
            }
            w << '\n';
        }
    });
}
}  // namespace

void save_obj(const TriangleMesh& mesh, const fs::path& path) {
    try {
        validate(mesh);
    } catch (const Error& e) {
        throw Error(path.string() + ": cannot save: " + e.what());
    }
    const bool with_materials = !mesh.materials.empty();
    fs::path mtl_path = path;
    mtl_path.replace_extension(".mtl");
    if (with_materials) write_mtl(mesh, mtl_path);

    write_atomically(path, [&](Writer& w) {
        w << "# written by librt save_obj: " << std::uint64_t{mesh.vertex_count()} << " vertices, "
          << std::uint64_t{mesh.triangle_count()} << " triangles\n";
        if (with_materials) w << "mtllib " << mtl_path.filename().string() << '\n';
        for (const glm::vec3& p : mesh.positions) {
            w << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        }
        for (const glm::vec2& t : mesh.uvs) w << "vt " << t.x << ' ' << t.y << '\n';
        for (const glm::vec3& n : mesh.normals) {
            w << "vn " << n.x << ' ' << n.y << ' ' << n.z << '\n';
        }
        const bool uvs = !mesh.uvs.empty(), normals = !mesh.normals.empty();
        const bool ids = with_materials && !mesh.material_ids.empty();
        std::size_t current = std::numeric_limits<std::size_t>::max();
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
            if (ids && mesh.material_ids[i] != current) {
                current = mesh.material_ids[i];
                w << "usemtl " << material_name(mesh, current) << '\n';
            }
            w << 'f';
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t index = std::uint64_t{mesh.triangles[i][k]} + 1;
                w << ' ' << index;
                if (uvs || normals) w << '/';
                if (uvs) w << index;
                if (normals) w << '/' << index;
            }
            w << '\n';
        }
    });
}

}  // namespace librt
