#include "forest.h"

#include <librt/core/error.h>
#include <librt/sampling/rng.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace librt::bench {
namespace {

constexpr float kCell = 1.2f;  // grid spacing, in units of a prototype's diagonal

/// Appends raw bytes of `values` to `bin`; returns the offset they start at.
template <class T>
std::size_t append(std::vector<char>& bin, const std::vector<T>& values) {
    const std::size_t offset = bin.size();
    const auto* bytes = reinterpret_cast<const char*>(values.data());
    bin.insert(bin.end(), bytes, bytes + values.size() * sizeof(T));
    return offset;  // every element is 4-byte multiples, so offsets stay aligned
}

/// A float as JSON, exactly (9 significant digits round-trip a float).
std::string num(float v) {
    std::ostringstream s;
    s << std::setprecision(9) << v;
    return s.str();
}

}  // namespace

void stand_on_ground(TriangleMesh& mesh) {
    const BBox b = mesh.bounds();
    const float scale = 1.0f / glm::length(b.diagonal());
    const glm::vec3 c = b.center();
    transform(mesh, make_transform(glm::vec3(scale), glm::vec3(0.0f),
                                   -scale * glm::vec3(c.x, b.lo.y, c.z)));
}

std::vector<ForestPlacement> forest_placements(std::span<const std::uint32_t> counts,
                                               std::uint64_t seed) {
    std::vector<std::uint32_t> kinds;
    for (std::uint32_t p = 0; p < counts.size(); ++p) kinds.insert(kinds.end(), counts[p], p);
    Pcg32 rng(seed, 40);
    // Fisher-Yates shuffle (Knuth, TAOCP vol. 2, 3.4.2, algorithm P); the modulo's bias
    // (below 2^-20 for these sizes) does not matter for a layout.
    for (std::size_t i = kinds.size(); i > 1; --i)
        std::swap(kinds[i - 1], kinds[rng.next_u32() % i]);
    const auto side = static_cast<std::uint32_t>(std::ceil(std::sqrt(double(kinds.size()))));
    const float half = 0.5f * kCell * float(side);
    std::vector<ForestPlacement> out;
    out.reserve(kinds.size());
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        const float angle = glm::two_pi<float>() * rng.next_float();
        const float scale = 0.7f + 0.6f * rng.next_float();
        const glm::vec2 jitter = 0.25f * kCell * (2.0f * rng.next_vec2() - 1.0f);
        const float x = kCell * (float(i % side) + 0.5f) - half + jitter.x;
        const float z = kCell * (float(i / side) + 0.5f) - half + jitter.y;
        glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.0f, z));
        m = glm::rotate(m, angle, glm::vec3(0.0f, 1.0f, 0.0f));
        m = glm::scale(m, glm::vec3(scale));
        out.push_back({kinds[i], m});
    }
    return out;
}

namespace {

/// Half the side of the ground quad: one cell wider than the grid on every side.
float ground_half(std::size_t instances) {
    return 0.5f * kCell * (std::ceil(std::sqrt(float(instances))) + 2.0f);
}

}  // namespace

ForestCamera forest_camera(std::size_t instances) {
    const float g = ground_half(instances);
    return {glm::vec3(0.0f, 0.55f * g, 1.45f * g), glm::vec3(0.0f, 0.0f, 0.1f * g)};
}

std::size_t placed_triangles(std::span<const TriangleMesh> prototypes,
                             std::span<const ForestPlacement> placements) {
    std::size_t n = 0;
    for (const ForestPlacement& p : placements) n += prototypes[p.prototype].triangle_count();
    return n;
}

void write_forest_gltf(const std::filesystem::path& dir, const std::string& name,
                       std::span<const TriangleMesh> prototypes,
                       std::span<const ForestPlacement> placements) {
    std::vector<char> bin;
    std::ostringstream views, accessors, meshes, materials, nodes;
    std::size_t view_count = 0, accessor_count = 0;
    const auto add_mesh = [&](const std::vector<glm::vec3>& positions,
                              const std::vector<glm::uvec3>& triangles, const glm::vec3& color) {
        const std::size_t pos_offset = append(bin, positions);
        const std::size_t idx_offset = append(bin, triangles);
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
        for (const glm::vec3& p : positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        views << (view_count ? "," : "") << "{\"buffer\":0,\"byteOffset\":" << pos_offset
              << ",\"byteLength\":" << positions.size() * 12 << ",\"target\":34962},"
              << "{\"buffer\":0,\"byteOffset\":" << idx_offset
              << ",\"byteLength\":" << triangles.size() * 12 << ",\"target\":34963}";
        accessors << (accessor_count ? "," : "") << "{\"bufferView\":" << view_count
                  << ",\"componentType\":5126,\"count\":" << positions.size()
                  << ",\"type\":\"VEC3\",\"min\":[" << num(lo.x) << "," << num(lo.y) << ","
                  << num(lo.z) << "],\"max\":[" << num(hi.x) << "," << num(hi.y) << "," << num(hi.z)
                  << "]},{\"bufferView\":" << view_count + 1
                  << ",\"componentType\":5125,\"count\":" << 3 * triangles.size()
                  << ",\"type\":\"SCALAR\"}";
        const std::size_t mesh = accessor_count / 2;
        meshes << (mesh ? "," : "")
               << "{\"primitives\":[{\"attributes\":{\"POSITION\":" << accessor_count
               << "},\"indices\":" << accessor_count + 1 << ",\"material\":" << mesh << "}]}";
        materials << (mesh ? "," : "") << "{\"pbrMetallicRoughness\":{\"baseColorFactor\":["
                  << num(color.r) << "," << num(color.g) << "," << num(color.b)
                  << ",1],\"metallicFactor\":0,\"roughnessFactor\":0.6}}";
        view_count += 2;
        accessor_count += 2;
        return mesh;
    };
    const glm::vec3 colors[] = {{0.35f, 0.55f, 0.25f}, {0.6f, 0.45f, 0.3f}, {0.5f, 0.5f, 0.6f}};
    for (std::size_t p = 0; p < prototypes.size(); ++p)
        add_mesh(prototypes[p].positions, prototypes[p].triangles, colors[p % 3]);

    const float g = ground_half(placements.size());
    const std::size_t ground =
        add_mesh({{-g, 0.0f, -g}, {g, 0.0f, -g}, {g, 0.0f, g}, {-g, 0.0f, g}},
                 {{0, 2, 1}, {0, 3, 2}}, {0.5f, 0.5f, 0.5f});

    std::size_t node_count = 0;
    const auto add_node = [&](const std::string& what, const glm::mat4& m) {
        nodes << (node_count++ ? "," : "") << "{" << what << ",\"matrix\":[";
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) nodes << (c + r ? "," : "") << num(m[c][r]);
        nodes << "]}";
    };
    for (const ForestPlacement& p : placements)
        add_node("\"mesh\":" + std::to_string(p.prototype), p.object_to_world);
    add_node("\"mesh\":" + std::to_string(ground), glm::mat4(1.0f));
    // glTF cameras look down their local -z, as lookAt's view space.
    const ForestCamera cam = forest_camera(placements.size());
    add_node("\"camera\":0", glm::inverse(glm::lookAt(cam.eye, cam.target, glm::vec3(0, 1, 0))));

    const std::filesystem::path bin_path = dir / (name + ".bin");
    const std::filesystem::path gltf_path = dir / (name + ".gltf");
    {
        std::ofstream out(bin_path, std::ios::binary);
        out.write(bin.data(), std::streamsize(bin.size()));
        if (!out) throw Error(bin_path.string() + ": cannot write");
    }
    std::ofstream out(gltf_path);
    out << "{\"asset\":{\"version\":\"2.0\",\"generator\":\"librt bench/scale\"},"
        << "\"buffers\":[{\"uri\":\"" << name << ".bin\",\"byteLength\":" << bin.size() << "}],"
        << "\"bufferViews\":[" << views.str() << "],\"accessors\":[" << accessors.str() << "],"
        << "\"materials\":[" << materials.str() << "],\"meshes\":[" << meshes.str() << "],"
        << "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.7,"
        << "\"aspectRatio\":1.3333333,\"znear\":0.01}}],"
        << "\"nodes\":[" << nodes.str() << "],\"scenes\":[{\"nodes\":[";
    for (std::size_t i = 0; i < node_count; ++i) out << (i ? "," : "") << i;
    out << "]}],\"scene\":0}\n";
    if (!out) throw Error(gltf_path.string() + ": cannot write");
}

}  // namespace librt::bench
