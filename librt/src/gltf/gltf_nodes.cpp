// The node graph: checked to be a forest (no cycles, one parent per node), then walked
// from the chosen scene's roots without recursion, composing transforms into the world
// matrices of instances, cameras and lights.

#include "gltf/gltf_internal.h"

#include <librt/core/constants.h>
#include <librt/core/untrusted_text.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace librt::gltf_detail {

namespace {

bool finite(const std::vector<double>& values) {
    for (const double v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

/// The node's local matrix: its matrix, else T * R * S (glTF 2.0 spec 3.5.3).
glm::mat4 local_matrix(const tinygltf::Node& node, const std::string& path, const Context& ctx) {
    const bool trs = !node.translation.empty() || !node.rotation.empty() || !node.scale.empty();
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) ctx.fail(path + ".matrix", "must have 16 numbers");
        if (!finite(node.matrix)) ctx.fail(path + ".matrix", "has a number that is not finite");
        if (trs) ctx.warn(path, "both matrix and translation/rotation/scale given; matrix used");
        // glTF stores matrices column by column, as glm does: the last row is elements 3, 7,
        // 11 and 15. The spec requires a matrix decomposable into TRS, so affine.
        const auto& e = node.matrix;
        if (e[3] != 0.0 || e[7] != 0.0 || e[11] != 0.0 || e[15] != 1.0) {
            ctx.fail(path + ".matrix", "not affine (last row " + number_text(e[3]) + " " +
                                           number_text(e[7]) + " " + number_text(e[11]) + " " +
                                           number_text(e[15]) + ", must be 0 0 0 1)");
        }
        glm::mat4 m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                m[c][r] = finite_float(node.matrix[std::size_t(c * 4 + r)],
                                       indexed(path + ".matrix", std::size_t(c * 4 + r)), ctx);
        return m;
    }
    glm::mat4 m(1.0f);
    if (!node.translation.empty()) {
        if (node.translation.size() != 3 || !finite(node.translation))
            ctx.fail(path + ".translation", "must be 3 finite numbers");
        glm::vec3 t;
        for (int i = 0; i < 3; ++i)
            t[i] = finite_float(node.translation[std::size_t(i)],
                                indexed(path + ".translation", std::size_t(i)), ctx);
        m = glm::translate(glm::mat4(1.0f), t);
    }
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4 || !finite(node.rotation))
            ctx.fail(path + ".rotation", "must be 4 finite numbers (x, y, z, w)");
        const double len =
            std::sqrt(node.rotation[0] * node.rotation[0] + node.rotation[1] * node.rotation[1] +
                      node.rotation[2] * node.rotation[2] + node.rotation[3] * node.rotation[3]);
        if (!(len > 0.0) || !std::isfinite(len))
            ctx.fail(path + ".rotation", "is a zero quaternion");
        // glTF gives (x, y, z, w); glm::quat takes (w, x, y, z). Renormalised: exporters
        // write unit quaternions rounded to a few digits.
        const glm::quat q(float(node.rotation[3] / len), float(node.rotation[0] / len),
                          float(node.rotation[1] / len), float(node.rotation[2] / len));
        m = m * glm::mat4_cast(q);
    }
    if (!node.scale.empty()) {
        if (node.scale.size() != 3 || !finite(node.scale))
            ctx.fail(path + ".scale", "must be 3 finite numbers");
        glm::vec3 s;
        for (int i = 0; i < 3; ++i)
            s[i] = finite_float(node.scale[std::size_t(i)],
                                indexed(path + ".scale", std::size_t(i)), ctx);
        m = glm::scale(m, s);
    }
    return m;
}

/// Parent of every node (-1 for roots), after checking the children lists form a forest.
std::vector<int> check_forest(const tinygltf::Model& model, const Context& ctx) {
    const std::size_t n = model.nodes.size();
    std::vector<int> parent(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& children = model.nodes[i].children;
        for (std::size_t k = 0; k < children.size(); ++k) {
            const std::string path = indexed(indexed("nodes", i) + ".children", k);
            const int c = children[k];
            check_index(ctx, path, c, n, "node");
            if (std::size_t(c) == i)
                ctx.fail(path, "node " + std::to_string(c) + " is its own child");
            if (parent[std::size_t(c)] != -1) {
                ctx.fail(path, "node " + std::to_string(c) + " is already a child of nodes[" +
                                   std::to_string(parent[std::size_t(c)]) +
                                   "] (a node has at most one parent)");
            }
            parent[std::size_t(c)] = int(i);
        }
    }
    // With one parent each, a cycle is a parent chain that comes back to itself.
    enum : unsigned char { Unknown, OnChain, Done };
    std::vector<unsigned char> state(n, Unknown);
    std::vector<int> chain;
    for (std::size_t i = 0; i < n; ++i) {
        chain.clear();
        int v = int(i);
        while (v != -1 && state[std::size_t(v)] == Unknown) {
            state[std::size_t(v)] = OnChain;
            chain.push_back(v);
            v = parent[std::size_t(v)];
        }
        if (v != -1 && state[std::size_t(v)] == OnChain) {
            std::string loop = std::to_string(v);
            for (int w = parent[std::size_t(v)]; w != v && loop.size() < 200;
                 w = parent[std::size_t(w)])
                loop = std::to_string(w) + " -> " + loop;
            ctx.fail(indexed("nodes", std::size_t(v)),
                     "the node graph has a cycle (child -> parent: " + std::to_string(v) + " -> " +
                         loop + ")");
        }
        for (const int w : chain) state[std::size_t(w)] = Done;
    }
    return parent;
}

GltfCamera read_camera(const tinygltf::Camera& cam, const std::string& path, const Context& ctx) {
    GltfCamera c;
    c.name = cam.name;
    // > 0 as the float librt keeps: 1e-300 rounds to 0 and 1e300 to infinity.
    auto positive = [&](double v, const std::string& where) {
        if (!(v > 0.0)) ctx.fail(where, number_text(v) + ": must be > 0");
        const float f = finite_float(v, where, ctx);
        if (!(f > 0.0f))
            ctx.fail(where, number_text(v) + ": must be > 0 (it rounds to 0 as a float)");
        return f;
    };
    if (cam.type == "perspective") {
        const auto& p = cam.perspective;
        c.type = GltfCamera::Type::Perspective;
        c.yfov = positive(p.yfov, path + ".perspective.yfov");
        if (p.yfov >= kPiDouble)
            ctx.fail(path + ".perspective.yfov", number_text(p.yfov) + ": must be < pi");
        c.znear = positive(p.znear, path + ".perspective.znear");
        if (p.aspectRatio != 0.0)
            c.aspect_ratio = positive(p.aspectRatio, path + ".perspective.aspectRatio");
        if (p.zfar != 0.0 && (!std::isfinite(p.zfar) || p.zfar <= p.znear))
            ctx.fail(path + ".perspective.zfar", number_text(p.zfar) + ": must be > znear");
        c.zfar = float(p.zfar);
    } else if (cam.type == "orthographic") {
        const auto& o = cam.orthographic;
        c.type = GltfCamera::Type::Orthographic;
        // The spec: xmag and ymag MUST NOT be zero and SHOULD NOT be negative (a negative
        // one mirrors the image, which librt does not do: it takes the magnitude).
        const auto magnitude = [&](double v, const char* name) {
            const std::string where = path + ".orthographic." + name;
            if (v == 0.0 || !std::isfinite(v) || !std::isfinite(float(v)) || float(v) == 0.0f)
                ctx.fail(where, number_text(v) + ": must be finite and not 0");
            if (v < 0.0) ctx.warn(where, number_text(v) + ": negative, its magnitude is used");
            return std::abs(float(v));
        };
        c.xmag = magnitude(o.xmag, "xmag");
        c.ymag = magnitude(o.ymag, "ymag");
        if (!(o.znear >= 0.0) || !std::isfinite(o.zfar) || !(o.zfar > o.znear)) {
            ctx.fail(path + ".orthographic", "znear = " + number_text(o.znear) + ", zfar = " +
                                                 number_text(o.zfar) + ": needs 0 <= znear < zfar");
        }
        c.znear = finite_float(o.znear, path + ".orthographic.znear", ctx);
        c.zfar = float(o.zfar);
    } else {
        ctx.fail(path + ".type",
                 quote_untrusted(cam.type) + ": must be perspective or orthographic");
    }
    return c;
}

GltfLight read_light(const tinygltf::Light& light, const std::string& path, const Context& ctx) {
    GltfLight l;
    l.name = light.name;
    if (light.type == "point")
        l.type = GltfLight::Type::Point;
    else if (light.type == "spot")
        l.type = GltfLight::Type::Spot;
    else if (light.type == "directional")
        l.type = GltfLight::Type::Directional;
    else
        ctx.fail(path + ".type",
                 quote_untrusted(light.type) + ": must be point, spot or directional");
    if (!light.color.empty()) {
        if (light.color.size() != 3 || !finite(light.color) || light.color[0] < 0 ||
            light.color[1] < 0 || light.color[2] < 0)
            ctx.fail(path + ".color", "must be 3 finite numbers >= 0");
        for (int i = 0; i < 3; ++i)
            l.color[i] = finite_float(light.color[std::size_t(i)],
                                      indexed(path + ".color", std::size_t(i)), ctx);
    }
    if (!std::isfinite(light.intensity) || light.intensity < 0)
        ctx.fail(path + ".intensity", number_text(light.intensity) + ": must be finite and >= 0");
    l.intensity = finite_float(light.intensity, path + ".intensity", ctx);
    if (!std::isfinite(light.range) || light.range < 0)
        ctx.fail(path + ".range", number_text(light.range) + ": must be > 0");
    // A range beyond float is as good as none (infinite).
    l.range = float(std::min(light.range, double(std::numeric_limits<float>::max())));
    if (l.type == GltfLight::Type::Spot) {
        const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
        if (!(inner >= 0.0) || !(inner < outer) || !(outer <= kPiDouble / 2 + 1e-6))
            ctx.fail(path + ".spot", "needs 0 <= innerConeAngle < outerConeAngle <= pi/2");
        l.inner_cone_angle = float(inner);
        l.outer_cone_angle = float(outer);
    }
    return l;
}

/// The node's KHR_lights_punctual light index, or -1.
int node_light(const tinygltf::Node& node, const std::string& path, std::size_t light_count,
               const Context& ctx) {
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end()) return -1;
    const std::string where = path + ".extensions.KHR_lights_punctual.light";
    if (!ext->second.IsObject() || !ext->second.Has("light") || !ext->second.Get("light").IsInt())
        ctx.fail(where, "missing or not an integer");
    const int index = ext->second.Get("light").Get<int>();
    check_index(ctx, where, index, light_count, "light");
    return index;
}

/// The name of an accessor type, for messages.
const char* type_name(int type) {
    return type == TINYGLTF_TYPE_VEC3 ? "VEC3" : type == TINYGLTF_TYPE_VEC4 ? "VEC4" : "?";
}

/// The instances of a node carrying EXT_mesh_gpu_instancing: one GltfInstance per element
/// of its TRANSLATION / ROTATION / SCALE accessors, world = the node's world * T * R * S
/// (the extension's rule). The node's mesh is placed by these alone, not by the node.
void add_gpu_instances(const tinygltf::Model& model, const tinygltf::Node& node, int index,
                       const glm::mat4& world, const tinygltf::Value& ext, const std::string& path,
                       Context& ctx, GltfScene& scene) {
    const std::string where = path + ".extensions.EXT_mesh_gpu_instancing";
    if (node.mesh == -1)
        ctx.fail(where, "the node places no mesh (the extension places copies of the node's mesh)");
    if (!ext.Has("attributes") || !ext.Get("attributes").IsObject())
        ctx.fail(where + ".attributes", "missing or not an object");
    const tinygltf::Value& attributes = ext.Get("attributes");
    struct Attribute {
        const char* name;
        int type;
        std::vector<float> values;  // empty when the attribute is absent
    };
    std::array<Attribute, 3> attr{{{"TRANSLATION", TINYGLTF_TYPE_VEC3, {}},
                                   {"ROTATION", TINYGLTF_TYPE_VEC4, {}},
                                   {"SCALE", TINYGLTF_TYPE_VEC3, {}}}};
    for (const std::string& key : attributes.Keys()) {
        const bool known = std::any_of(attr.begin(), attr.end(),
                                       [&](const Attribute& a) { return key == a.name; });
        // Names starting with "_" are the application's own (the extension allows them).
        if (!known && key.rfind('_', 0) != 0)
            ctx.warn(where + ".attributes",
                     quote_untrusted(key) + ": not an attribute of the extension; ignored");
    }
    std::size_t count = 0;
    const char* count_from = nullptr;
    for (Attribute& a : attr) {
        if (!attributes.Has(a.name)) continue;
        const std::string at = where + ".attributes." + a.name;
        const tinygltf::Value& v = attributes.Get(a.name);
        if (!v.IsInt()) ctx.fail(at, "must be an accessor index");
        const int accessor = v.Get<int>();
        check_index(ctx, at, accessor, model.accessors.size(), "accessor");
        const tinygltf::Accessor& acc = model.accessors[std::size_t(accessor)];
        const std::string acc_path = at + ": " + indexed("accessors", std::size_t(accessor));
        if (acc.type != a.type)
            ctx.fail(acc_path + ".type", std::string("must be ") + type_name(a.type));
        // The extension's component types: floats, or (KHR_mesh_quantization) signed bytes
        // and shorts; a rotation's integers normalised, as a unit quaternion's must be.
        const int ct = acc.componentType;
        const bool small_int =
            ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT;
        const bool rotation = a.type == TINYGLTF_TYPE_VEC4;
        if (ct != TINYGLTF_COMPONENT_TYPE_FLOAT && !(small_int && (!rotation || acc.normalized)))
            ctx.fail(acc_path + ".componentType",
                     std::to_string(ct) + (rotation ? ": must be FLOAT, or normalized BYTE or SHORT"
                                                    : ": must be FLOAT, BYTE or SHORT"));
        if (count_from != nullptr && acc.count != count) {
            ctx.fail(at, indexed("accessors", std::size_t(accessor)) + " has " +
                             std::to_string(acc.count) + " elements, " + count_from + "'s has " +
                             std::to_string(count) + " (one element per instance in each)");
        }
        count = acc.count;
        count_from = a.name;
        int components = 0;
        a.values = read_float_accessor(model, accessor, {a.type}, at, ctx, &components);
    }
    if (count_from == nullptr)
        ctx.fail(where + ".attributes", "has none of TRANSLATION, ROTATION and SCALE");
    // Each instance keeps the node's name: charged with it, so a long name repeated over
    // many instances cannot take unbounded memory.
    const std::uint64_t each = sizeof(GltfInstance) + node.name.size();
    if (count > std::numeric_limits<std::uint64_t>::max() / each)
        ctx.fail(where, std::to_string(count) + " instances: too many");
    ctx.spend(count * each, where);
    scene.instances.reserve(scene.instances.size() + count);
    const std::vector<float>& t = attr[0].values;
    const std::vector<float>& r = attr[1].values;
    const std::vector<float>& sc = attr[2].values;
    for (std::size_t i = 0; i < count; ++i) {
        glm::mat4 m(1.0f);
        if (!t.empty()) m = glm::translate(m, glm::vec3(t[3 * i], t[3 * i + 1], t[3 * i + 2]));
        if (!r.empty()) {
            // (x, y, z, w) as for a node's rotation; renormalised (quantised or rounded).
            const glm::vec4 q(r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]);
            const float len = glm::length(q);
            if (!(len > 0.0f) || !std::isfinite(len)) {
                ctx.fail(where + ".attributes.ROTATION",
                         "element " + std::to_string(i) + " is a zero quaternion");
            }
            m = m * glm::mat4_cast(glm::quat(q.w / len, q.x / len, q.y / len, q.z / len));
        }
        if (!sc.empty()) m = glm::scale(m, glm::vec3(sc[3 * i], sc[3 * i + 1], sc[3 * i + 2]));
        const glm::mat4 placed = world * m;
        const float* w = glm::value_ptr(placed);
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(w[k]))
                ctx.fail(where,
                         "instance " + std::to_string(i) + ": its world transform overflows float");
        GltfInstance inst{node.mesh, index, placed, node.name};
        inst.gpu_instance = int(i);
        scene.instances.push_back(std::move(inst));
    }
}

}  // namespace

void read_nodes(const tinygltf::Model& model, int scene_index, Context& ctx, GltfScene& scene) {
    std::vector<GltfCamera> cameras;
    for (std::size_t i = 0; i < model.cameras.size(); ++i)
        cameras.push_back(read_camera(model.cameras[i], indexed("cameras", i), ctx));
    std::vector<GltfLight> lights;
    for (std::size_t i = 0; i < model.lights.size(); ++i)
        lights.push_back(
            read_light(model.lights[i], indexed("extensions.KHR_lights_punctual.lights", i), ctx));
    const std::vector<int> parent = check_forest(model, ctx);

    std::vector<int> roots;
    std::string roots_path;
    if (scene_index < 0 && model.defaultScene != -1) {
        check_index(ctx, "scene", model.defaultScene, model.scenes.size(), "scene");
        scene_index = model.defaultScene;
    }
    if (scene_index < 0 && !model.scenes.empty()) scene_index = 0;
    if (scene_index >= 0) {
        if (const std::size_t n = model.scenes.size(); std::size_t(scene_index) >= n) {
            ctx.fail("scenes",
                     "scene " + std::to_string(scene_index) + " requested, the file has " +
                         (n == 0 ? std::string("none")
                                 : std::to_string(n) +
                                       (n == 1 ? " (scene 0)"
                                               : " (scenes 0 to " + std::to_string(n - 1) + ")")));
        }
        roots = model.scenes[std::size_t(scene_index)].nodes;
        roots_path = indexed("scenes", std::size_t(scene_index)) + ".nodes";
    } else {
        ctx.warn("scenes", "none in the file: every root node is placed");
        for (std::size_t i = 0; i < parent.size(); ++i)
            if (parent[i] == -1) roots.push_back(int(i));
        roots_path = "nodes";
    }
    std::vector<unsigned char> seen(model.nodes.size(), 0);
    std::vector<std::pair<int, glm::mat4>> stack;
    for (std::size_t k = 0; k < roots.size(); ++k) {
        const std::string path = indexed(roots_path, k);
        const int r = roots[k];
        check_index(ctx, path, r, model.nodes.size(), "node");
        if (parent[std::size_t(r)] != -1) {
            ctx.fail(path, "node " + std::to_string(r) + " is a child of nodes[" +
                               std::to_string(parent[std::size_t(r)]) + "], not a root");
        }
        if (seen[std::size_t(r)]) ctx.fail(path, "node " + std::to_string(r) + " is listed twice");
        seen[std::size_t(r)] = 1;
    }
    // Roots pushed last-first, as children below, so nodes are visited in file order.
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, glm::mat4(1.0f));
    while (!stack.empty()) {
        const auto [index, parent_world] = stack.back();
        stack.pop_back();
        const tinygltf::Node& node = model.nodes[std::size_t(index)];
        const std::string path = indexed("nodes", std::size_t(index));
        const glm::mat4 world = parent_world * local_matrix(node, path, ctx);
        const float* w = glm::value_ptr(world);
        for (int i = 0; i < 16; ++i)
            if (!std::isfinite(w[i]))
                ctx.fail(path,
                         "its world transform (its own composed with its ancestors') "
                         "overflows float");
        if (node.skin != -1)
            ctx.warn(path + ".skin", "skinning ignored: the mesh is placed by the node");
        if (node.mesh != -1)
            check_index(ctx, path + ".mesh", node.mesh, model.meshes.size(), "mesh");
        if (const auto gpu = node.extensions.find("EXT_mesh_gpu_instancing");
            gpu != node.extensions.end())
            add_gpu_instances(model, node, index, world, gpu->second, path, ctx, scene);
        else if (node.mesh != -1)
            scene.instances.push_back({node.mesh, index, world, node.name});
        if (node.camera != -1) {
            check_index(ctx, path + ".camera", node.camera, cameras.size(), "camera");
            GltfCamera c = cameras[std::size_t(node.camera)];
            if (c.name.empty()) c.name = node.name;
            c.camera = node.camera;
            c.node = index;
            c.world = world;
            scene.cameras.push_back(std::move(c));
        }
        if (const int li = node_light(node, path, lights.size(), ctx); li >= 0) {
            GltfLight l = lights[std::size_t(li)];
            if (l.name.empty()) l.name = node.name;
            l.light = li;
            l.node = index;
            l.world = world;
            scene.lights.push_back(std::move(l));
        }
        // Children pushed last-first so they are visited in file order. Each node has one
        // parent and the graph no cycle (check_forest), so every node is visited once.
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
            stack.emplace_back(*c, world);
    }
}

}  // namespace librt::gltf_detail
