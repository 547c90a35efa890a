// glTF meshes to GltfMesh: attributes read and checked, indices range-checked, strips and
// fans turned into triangles.

#include "gltf/gltf_internal.h"

#include <librt/core/untrusted_text.h>
#include <librt/geometry/mesh.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>

namespace librt::gltf_detail {

namespace {

template <int N>
std::vector<glm::vec<N, float>> to_vectors(const std::vector<float>& flat) {
    std::vector<glm::vec<N, float>> out(flat.size() / N);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (int j = 0; j < N; ++j) out[i][j] = flat[i * N + std::size_t(j)];
    return out;
}

/// Whether attribute `name` may be stored as `component_type` (normalised or not): the
/// glTF 2.0 specification's table of vertex attributes (section 3.7.2.1), widened by
/// KHR_mesh_quantization's table when the file lists that extension in extensionsUsed.
bool attribute_format_allowed(std::string_view name, int component_type, bool normalized,
                              bool quantized) {
    const bool f = component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool ub = component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    const bool us = component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    const bool b = component_type == TINYGLTF_COMPONENT_TYPE_BYTE;
    const bool s = component_type == TINYGLTF_COMPONENT_TYPE_SHORT;
    if (f) return !normalized;
    if (name == "COLOR_0") return (ub || us) && normalized;
    if (name == "TEXCOORD_0" || name == "TEXCOORD_1")
        return quantized ? (ub || us || b || s) : ((ub || us) && normalized);
    if (name == "POSITION") return quantized && (ub || us || b || s);
    // NORMAL and TANGENT: signed and normalised only.
    return quantized && (b || s) && normalized;
}

/// Fails unless accessor `index` stores attribute `name` in a format the file may use.
void check_attribute_format(const tinygltf::Model& model, int index, std::string_view name,
                            const std::string& path, const Context& ctx) {
    const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
    const auto& used = model.extensionsUsed;
    const bool quantized =
        std::find(used.begin(), used.end(), "KHR_mesh_quantization") != used.end();
    if (attribute_format_allowed(name, a.componentType, a.normalized, quantized)) return;
    std::string what = "componentType " + std::to_string(a.componentType) +
                       (a.normalized ? " (normalized)" : "") + " is not allowed for " +
                       std::string(name);
    if (!quantized && attribute_format_allowed(name, a.componentType, a.normalized, true))
        what += " unless KHR_mesh_quantization is in extensionsUsed";
    ctx.fail(path + ": " + indexed("accessors", std::size_t(index)) + ".componentType", what);
}

/// The floats of attribute `name`, from the primitive's Draco stream when it holds that
/// attribute, else from its accessor.
std::vector<float> read_values(const tinygltf::Model& model, int accessor, std::string_view name,
                               const std::vector<int>& types, const std::string& path, Context& ctx,
                               const DracoPrimitive* draco, int* components) {
    if (draco != nullptr) {
        if (const auto it = draco->attributes.find(name); it != draco->attributes.end()) {
            const tinygltf::Accessor& a = model.accessors[std::size_t(accessor)];
            if (std::find(types.begin(), types.end(), a.type) == types.end())
                ctx.fail(path + ": " + indexed("accessors", std::size_t(accessor)) + ".type",
                         "not a type this attribute can have");
            *components = int(it->second.size() / std::max<std::size_t>(a.count, 1));
            return it->second;
        }
    }
    return read_float_accessor(model, accessor, types, path, ctx, components);
}

/// Reads attribute `name` when present, checking its count; empty when absent.
template <int N>
std::vector<glm::vec<N, float>> attribute(const tinygltf::Model& model,
                                          const tinygltf::Primitive& prim, const char* name,
                                          const std::vector<int>& types, std::size_t count,
                                          const std::string& path, Context& ctx,
                                          const DracoPrimitive* draco) {
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return {};
    const std::string at = path + ".attributes." + name;
    check_index(ctx, at, it->second, model.accessors.size(), "accessor");
    check_attribute_format(model, it->second, name, at, ctx);
    if (accessor_count(model, it->second) != count) {
        ctx.fail(at, "count " + std::to_string(accessor_count(model, it->second)) +
                         " differs from POSITION's " + std::to_string(count));
    }
    int components = 0;
    const std::vector<float> flat =
        read_values(model, it->second, name, types, at, ctx, draco, &components);
    if (N == 4 && components == 3) {  // COLOR_0 as RGB: alpha 1
        std::vector<glm::vec<N, float>> out(count);
        for (std::size_t i = 0; i < count; ++i)
            for (int j = 0; j < N; ++j) out[i][j] = j < 3 ? flat[i * 3 + std::size_t(j)] : 1.0f;
        return out;
    }
    return to_vectors<N>(flat);
}

/// Triangles of `mode` from the vertex sequence `order` (indices, or 0..n-1).
std::vector<glm::uvec3> assemble(int mode, const std::vector<std::uint32_t>& order,
                                 const std::string& path, Context& ctx) {
    const std::size_t n = order.size();
    std::vector<glm::uvec3> tris;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3 != 0) {
            ctx.warn(path, std::to_string(n) + " vertices is not a multiple of 3: the last " +
                               std::to_string(n % 3) + " ignored");
        }
        ctx.spend(n / 3 * sizeof(glm::uvec3), path);
        tris.reserve(n / 3);
        for (std::size_t i = 0; i + 2 < n; i += 3)
            tris.push_back({order[i], order[i + 1], order[i + 2]});
        return tris;
    }
    if (n < 3) return tris;
    ctx.spend((n - 2) * sizeof(glm::uvec3), path);
    tris.reserve(n - 2);
    for (std::size_t i = 0; i + 2 < n; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // glTF 2.0 spec 3.7.2.1: triangle i is {v_i, v_(i+1+i%2), v_(i+2-i%2)}, which keeps
            // every triangle's winding the same as the first one's.
            const std::size_t odd = i % 2;
            tris.push_back({order[i], order[i + 1 + odd], order[i + 2 - odd]});
        } else {
            // Fan, same section: triangle i is {v_(i+1), v_(i+2), v_0}.
            tris.push_back({order[i + 1], order[i + 2], order[0]});
        }
    }
    return tris;
}

const std::vector<int> kVec2{TINYGLTF_TYPE_VEC2};
const std::vector<int> kVec3{TINYGLTF_TYPE_VEC3};
const std::vector<int> kVec4{TINYGLTF_TYPE_VEC4};
const std::vector<int> kVec34{TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4};

/// The material of a primitive with KHR_materials_variants mappings under `variant` (-1:
/// none chosen): the mapping's that lists the variant, else `material`. Every mapping is
/// checked, whichever variant is chosen, so a file is refused or not whatever the option.
int variant_material(const tinygltf::Model& model, const tinygltf::Value& ext,
                     const std::string& path, int variant, std::size_t variant_count, int material,
                     const Context& ctx) {
    const std::string where = path + ".extensions.KHR_materials_variants.mappings";
    if (!ext.Has("mappings") || !ext.Get("mappings").IsArray())
        ctx.fail(where, "missing, empty or not an array");
    const tinygltf::Value& mappings = ext.Get("mappings");
    std::vector<int> mapped_by(variant_count, -1);  // the mapping naming each variant
    int chosen = material;
    for (std::size_t k = 0; k < mappings.ArrayLen(); ++k) {
        const tinygltf::Value& m = mappings.Get(int(k));
        const std::string at = indexed(where, k);
        if (!m.IsObject()) ctx.fail(at, "must be an object");
        if (!m.Has("material") || !m.Get("material").IsInt())
            ctx.fail(at + ".material", "missing or not an integer");
        const int mat = m.Get("material").Get<int>();
        check_index(ctx, at + ".material", mat, model.materials.size(), "material");
        if (!m.Has("variants") || !m.Get("variants").IsArray())
            ctx.fail(at + ".variants", "missing, empty or not an array of variant indices");
        const tinygltf::Value& variants = m.Get("variants");
        for (std::size_t j = 0; j < variants.ArrayLen(); ++j) {
            const std::string vat = indexed(at + ".variants", j);
            if (!variants.Get(int(j)).IsInt()) ctx.fail(vat, "must be an integer");
            const int v = variants.Get(int(j)).Get<int>();
            check_index(ctx, vat, v, variant_count, "variant");
            // The extension: a variant maps to one material per primitive.
            if (mapped_by[std::size_t(v)] != -1)
                ctx.fail(vat, "variant " + std::to_string(v) + " is mapped already by " +
                                  indexed("mappings", std::size_t(mapped_by[std::size_t(v)])));
            mapped_by[std::size_t(v)] = int(k);
            if (v == variant) chosen = mat;
        }
    }
    return chosen;
}

}  // namespace

int read_variants(const tinygltf::Model& model, const std::string& wanted, const Context& ctx,
                  GltfScene& scene) {
    const std::string where = "extensions.KHR_materials_variants";
    if (const auto ext = model.extensions.find("KHR_materials_variants");
        ext != model.extensions.end()) {
        const tinygltf::Value& e = ext->second;
        if (!e.Has("variants") || !e.Get("variants").IsArray())
            ctx.fail(where + ".variants", "missing, empty or not an array");
        const tinygltf::Value& list = e.Get("variants");
        for (std::size_t i = 0; i < list.ArrayLen(); ++i) {
            const tinygltf::Value& v = list.Get(int(i));
            if (!v.IsObject() || !v.Has("name") || !v.Get("name").IsString())
                ctx.fail(indexed(where + ".variants", i) + ".name", "missing or not a string");
            scene.variants.push_back(v.Get("name").Get<std::string>());
        }
    }
    if (wanted.empty()) return -1;
    for (std::size_t i = 0; i < scene.variants.size(); ++i)
        if (scene.variants[i] == wanted) return int(i);
    // The names the file defines, each quoted (escaped, capped), at most 32 of them.
    std::string names;
    for (std::size_t i = 0; i < scene.variants.size() && i < 32; ++i)
        names += (i == 0 ? "" : ", ") + quote_untrusted(scene.variants[i]);
    if (scene.variants.size() > 32)
        names += " and " + std::to_string(scene.variants.size() - 32) + " more";
    ctx.fail(where, "variant " + quote_untrusted(wanted) + " is not in the file (" +
                        (names.empty() ? std::string("it defines no variants")
                                       : "its variants: " + names) +
                        ")");
}

void read_meshes(const tinygltf::Model& model, int variant, Context& ctx, GltfScene& scene) {
    scene.meshes.reserve(model.meshes.size());
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
        const tinygltf::Mesh& mesh = model.meshes[m];
        GltfMesh out;
        out.name = mesh.name;
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            const std::string path = indexed(indexed("meshes", m) + ".primitives", p);
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode < TINYGLTF_MODE_TRIANGLES) {
                ctx.warn(path, "points and lines are not rendered; primitive skipped");
                continue;
            }
            if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
                ctx.fail(path + ".mode", std::to_string(mode) + " is not a glTF mode");
            if (prim.material != -1)
                check_index(ctx, path + ".material", prim.material, model.materials.size(),
                            "material");
            const auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) {
                ctx.warn(path, "no POSITION attribute; primitive skipped");
                continue;
            }
            if (!prim.targets.empty()) ctx.warn(path, "morph targets ignored (base shape used)");
            GltfPrimitive g;
            g.material = prim.material;
            if (const auto v = prim.extensions.find("KHR_materials_variants");
                v != prim.extensions.end())
                g.material = variant_material(model, v->second, path, variant,
                                              scene.variants.size(), prim.material, ctx);
            int components = 0;
            const std::string pos_path = path + ".attributes.POSITION";
            check_index(ctx, pos_path, pos->second, model.accessors.size(), "accessor");
            check_attribute_format(model, pos->second, "POSITION", pos_path, ctx);
            // KHR_draco_mesh_compression: attributes and indices come from its stream.
            std::unique_ptr<DracoPrimitive> draco;
            if (has_draco(prim))
                draco = std::make_unique<DracoPrimitive>(decode_draco(model, prim, path, ctx));
            g.positions = to_vectors<3>(read_values(model, pos->second, "POSITION", kVec3, pos_path,
                                                    ctx, draco.get(), &components));
            const std::size_t count = g.positions.size();
            // Refused here, where the accessor's path is known (TriangleMesh's own check
            // would come later, naming neither file nor accessor).
            for (std::size_t i = 0; i < count; ++i) {
                const glm::vec3& q = g.positions[i];
                const float largest = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
                if (largest > kMaxMeshCoordinate) {
                    ctx.fail(pos_path, "vertex " + std::to_string(i) + " = (" + number_text(q.x) +
                                           ", " + number_text(q.y) + ", " + number_text(q.z) +
                                           "): coordinate " + number_text(largest) +
                                           " exceeds 2^40 (1.1e12), the largest librt traces "
                                           "(ray distances to it would overflow float)");
                }
            }
            g.normals = attribute<3>(model, prim, "NORMAL", kVec3, count, path, ctx, draco.get());
            g.tangents = attribute<4>(model, prim, "TANGENT", kVec4, count, path, ctx, draco.get());
            g.uv0 = attribute<2>(model, prim, "TEXCOORD_0", kVec2, count, path, ctx, draco.get());
            g.uv1 = attribute<2>(model, prim, "TEXCOORD_1", kVec2, count, path, ctx, draco.get());
            g.colors = attribute<4>(model, prim, "COLOR_0", kVec34, count, path, ctx, draco.get());
            std::vector<std::uint32_t> order;
            if (draco != nullptr) {
                order = std::move(draco->indices);  // checked against the point count
            } else if (prim.indices != -1) {
                const std::string ip = path + ".indices";
                order = read_index_accessor(model, prim.indices, ip, ctx);
                for (std::size_t i = 0; i < order.size(); ++i) {
                    if (order[i] >= count) {
                        ctx.fail(ip, "index " + std::to_string(order[i]) + " >= vertex count " +
                                         std::to_string(count) + " (at position " +
                                         std::to_string(i) + ")");
                    }
                }
            } else {
                ctx.spend(count * sizeof(std::uint32_t), path);
                order.resize(count);
                for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::uint32_t>(i);
            }
            g.triangles = assemble(mode, order, path, ctx);
            out.primitives.push_back(std::move(g));
        }
        scene.meshes.push_back(std::move(out));
    }
}

}  // namespace librt::gltf_detail
