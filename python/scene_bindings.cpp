// Scenes built in Python: materials, textures, spheres, meshes from NumPy arrays, instances,
// lights, cameras, and ray queries on a committed scene (docs/python.md, "Scenes in code").

#include "bindings.h"

#include <librt/core/error.h>
#include <librt/geometry/bbox.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/ray.h>
#include <librt/light/directional_light.h>
#include <librt/light/disk_light.h>
#include <librt/light/environment_light.h>
#include <librt/light/point_light.h>
#include <librt/light/quad_light.h>
#include <librt/light/sphere_light.h>
#include <librt/light/spot_light.h>
#include <librt/light/triangle_light.h>
#include <librt/material/material.h>
#include <librt/material/texture.h>

#include <glm/mat4x4.hpp>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace librt::python {

void PyScene::ensure_committed() {
    if (scene.committed()) return;
    // Another thread may be committing it (its GIL released): one commit at a time.
    Scene& s = mutable_scene();
    const SceneInUse guard(*this);
    py::gil_scoped_release release;
    s.commit();
}

Scene& PyScene::mutable_scene() {
    if (in_use > 0) throw Error("scene: cannot be changed while a render or ray query uses it");
    return scene;
}

namespace {

/// A C-contiguous copy (or view) of `a` as T with shape (n, columns); throws librt::Error
/// naming `what` for another shape.
template <typename T>
py::array_t<T, py::array::c_style | py::array::forcecast> rows_of(const py::handle& a,
                                                                  std::size_t columns,
                                                                  const char* what) {
    auto arr = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!arr || arr.ndim() != 2 || static_cast<std::size_t>(arr.shape(1)) != columns)
        throw Error(std::string(what) + ": expected an array of shape (N, " +
                    std::to_string(columns) + ")");
    return arr;
}

/// A TriangleMesh from NumPy arrays: vertices float N x 3, indices uint32 M x 3, optional
/// normals N x 3 and uvs N x 2. Scene::add_mesh validates the rest (indices in range,
/// finite positions) and throws librt::Error naming what is wrong.
TriangleMesh mesh_from_arrays(const py::handle& vertices, const py::handle& indices,
                              const py::handle& normals, const py::handle& uvs) {
    TriangleMesh mesh;
    const auto v = rows_of<float>(vertices, 3, "vertices");
    // Indices must be integers: a float array is refused rather than truncated.
    const auto idx = py::array::ensure(indices);
    if (!idx || (idx.dtype().kind() != 'i' && idx.dtype().kind() != 'u'))
        throw Error("indices: expected an integer array of shape (M, 3)");
    const auto i64 = rows_of<std::int64_t>(indices, 3, "indices");
    mesh.positions.resize(static_cast<std::size_t>(v.shape(0)));
    std::memcpy(mesh.positions.data(), v.data(), mesh.positions.size() * sizeof(glm::vec3));
    mesh.triangles.resize(static_cast<std::size_t>(i64.shape(0)));
    const std::int64_t* ip = i64.data();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int c = 0; c < 3; ++c) {
            const std::int64_t x = ip[3 * t + static_cast<std::size_t>(c)];
            if (x < 0 || x > std::int64_t{std::numeric_limits<std::uint32_t>::max()})
                throw Error("indices[" + std::to_string(t) + "][" + std::to_string(c) +
                            "]: " + std::to_string(x) + " is not a vertex index");
            mesh.triangles[t][c] = static_cast<std::uint32_t>(x);
        }
    }
    if (!normals.is_none()) {
        const auto n = rows_of<float>(normals, 3, "normals");
        if (n.shape(0) != v.shape(0)) throw Error("normals: expected one per vertex");
        mesh.normals.resize(mesh.positions.size());
        std::memcpy(mesh.normals.data(), n.data(), mesh.normals.size() * sizeof(glm::vec3));
    }
    if (!uvs.is_none()) {
        const auto u = rows_of<float>(uvs, 2, "uvs");
        if (u.shape(0) != v.shape(0)) throw Error("uvs: expected one per vertex");
        mesh.uvs.resize(mesh.positions.size());
        std::memcpy(mesh.uvs.data(), u.data(), mesh.uvs.size() * sizeof(glm::vec2));
    }
    return mesh;
}

/// A mat4 from a 4 x 4 array, row-major as NumPy writes matrices (translation in the last
/// column); glm stores columns.
glm::mat4 mat4_from_array(const py::handle& a) {
    const auto arr = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!arr || arr.ndim() != 2 || arr.shape(0) != 4 || arr.shape(1) != 4)
        throw Error("transform: expected a 4 x 4 array");
    glm::mat4 m(1.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = arr.at(r, c);
    return m;
}

/// The material of `kind` with its defaults, before the keyword arguments.
Material material_of_kind(const std::string& kind) {
    if (kind == "diffuse") return Material::diffuse(glm::vec3(0.8f));
    if (kind == "mirror") return Material::mirror();
    if (kind == "dielectric") return Material::dielectric(1.5f);
    if (kind == "rough_dielectric") return Material::rough_dielectric(1.5f, 0.2f);
    if (kind == "conductor") return Material::conductor(Metal::Aluminium, 0.2f);
    if (kind == "metallic_roughness")
        return Material::metallic_roughness(glm::vec3(1.0f), 0.0f, 0.5f);
    if (kind == "emissive") return Material::emissive(glm::vec3(1.0f));
    throw Error("Material kind: '" + kind +
                "' is none of diffuse, mirror, dielectric, rough_dielectric, conductor, "
                "metallic_roughness, emissive");
}

Metal metal_of(const std::string& name) {
    if (name == "gold") return Metal::Gold;
    if (name == "silver") return Metal::Silver;
    if (name == "copper") return Metal::Copper;
    if (name == "aluminium" || name == "aluminum") return Metal::Aluminium;
    throw Error("metal: '" + name + "' is none of gold, silver, copper, aluminium");
}

const char* kind_name(MaterialKind k) {
    switch (k) {
        case MaterialKind::Diffuse:
            return "diffuse";
        case MaterialKind::Mirror:
            return "mirror";
        case MaterialKind::Dielectric:
            return "dielectric";
        case MaterialKind::Emissive:
            return "emissive";
        case MaterialKind::Conductor:
            return "conductor";
        case MaterialKind::RoughDielectric:
            return "rough_dielectric";
        case MaterialKind::MetallicRoughness:
            return "metallic_roughness";
    }
    return "?";
}

/// Texture slots as plain texture ids in Python (the slot's uv transform stays the identity).
template <TextureSlot Material::*Slot>
void texture_slot(py::class_<Material>& c, const char* name) {
    c.def_property(
        name, [](const Material& m) { return (m.*Slot).texture; },
        [](Material& m, std::int32_t id) { (m.*Slot).texture = id; });
}

void bind_material(py::module_& m) {
    py::class_<Material> c(m, "Material",
                           "A surface: Material(kind='diffuse', **fields), every field a keyword");
    c.def(py::init([](const std::string& kind, const py::kwargs& kwargs) {
              Material base = material_of_kind(kind);
              if (kwargs.contains("metal")) {
                  const float roughness =
                      kwargs.contains("roughness") ? kwargs["roughness"].cast<float>() : 0.2f;
                  base =
                      Material::conductor(metal_of(kwargs["metal"].cast<std::string>()), roughness);
              }
              // Set each keyword as the attribute of the same name, so that the keywords
              // are exactly the fields (an unknown one is a TypeError naming it).
              py::object obj = py::cast(base);
              for (const auto& [key, value] : kwargs) {
                  const std::string k = key.cast<std::string>();
                  if (k == "metal") continue;
                  if (k == "kind" || !py::hasattr(obj, k.c_str()))
                      throw py::type_error("Material: unknown keyword '" + k + "'");
                  obj.attr(k.c_str()) = value;
              }
              return obj.cast<Material>();
          }),
          py::arg("kind") = "diffuse");
    c.def_property_readonly("kind", [](const Material& mat) { return kind_name(mat.kind); });
    c.def_readwrite("albedo", &Material::albedo)
        .def_readwrite("albedo_texture", &Material::albedo_texture)
        .def_readwrite("ior", &Material::ior)
        .def_readwrite("fresnel", &Material::fresnel)
        .def_readwrite("emission", &Material::emission)
        .def_readwrite("roughness", &Material::roughness)
        .def_readwrite("eta", &Material::eta)
        .def_readwrite("k", &Material::k)
        .def_readwrite("base_color", &Material::base_color)
        .def_readwrite("metallic", &Material::metallic)
        .def_readwrite("transmission", &Material::transmission)
        .def_readwrite("normal_scale", &Material::normal_scale)
        .def_readwrite("alpha", &Material::alpha)
        .def_readwrite("alpha_cutoff", &Material::alpha_cutoff)
        .def_readwrite("double_sided", &Material::double_sided)
        .def_readwrite("unlit", &Material::unlit)
        .def_readwrite("anisotropy", &Material::anisotropy)
        .def_readwrite("anisotropy_rotation", &Material::anisotropy_rotation)
        .def_readwrite("clearcoat", &Material::clearcoat)
        .def_readwrite("clearcoat_roughness", &Material::clearcoat_roughness)
        .def_readwrite("specular", &Material::specular)
        .def_readwrite("specular_color", &Material::specular_color)
        .def_readwrite("sheen_color", &Material::sheen_color)
        .def_readwrite("sheen_roughness", &Material::sheen_roughness)
        .def_readwrite("occlusion_strength", &Material::occlusion_strength);
    texture_slot<&Material::base_color_texture>(c, "base_color_texture");
    texture_slot<&Material::metallic_roughness_texture>(c, "metallic_roughness_texture");
    texture_slot<&Material::emission_texture>(c, "emission_texture");
    texture_slot<&Material::normal_texture>(c, "normal_texture");
    texture_slot<&Material::anisotropy_texture>(c, "anisotropy_texture");
    texture_slot<&Material::clearcoat_texture>(c, "clearcoat_texture");
    texture_slot<&Material::clearcoat_roughness_texture>(c, "clearcoat_roughness_texture");
    texture_slot<&Material::sheen_color_texture>(c, "sheen_color_texture");
    texture_slot<&Material::sheen_roughness_texture>(c, "sheen_roughness_texture");
    texture_slot<&Material::specular_texture>(c, "specular_texture");
    texture_slot<&Material::specular_color_texture>(c, "specular_color_texture");
    texture_slot<&Material::transmission_texture>(c, "transmission_texture");
    texture_slot<&Material::occlusion_texture>(c, "occlusion_texture");
    c.def("__repr__", [](const Material& mat) {
        return std::string("<librt.Material ") + kind_name(mat.kind) + ">";
    });
}

const char* projection_name(Projection p) {
    return p == Projection::Orthographic ? "orthographic" : "perspective";
}

const char* lens_name(LensModel l) {
    switch (l) {
        case LensModel::Pinhole:
            return "pinhole";
        case LensModel::Gaussian:
            return "gaussian";
        case LensModel::Disk:
            return "thin_lens";
    }
    return "?";
}

void bind_camera(py::module_& m) {
    // CameraSettings: validated when a render or query builds the Camera from it.
    py::class_<CameraSettings> c(m, "Camera",
                                 "A camera: position, target, up, projection, field of view, "
                                 "size and lens (librt/film/camera.h's CameraSettings)");
    c.def(py::init([](const py::kwargs& kwargs) {
        CameraSettings s;
        s.pixel_jitter = PixelJitter::Gaussian;  // anti-aliased, as rt_render renders
        py::object obj = py::cast(s);
        for (const auto& [key, value] : kwargs) {
            const std::string k = key.cast<std::string>();
            if (!py::hasattr(obj, k.c_str()) || k == "look_at")
                throw py::type_error("Camera: unknown keyword '" + k + "'");
            obj.attr(k.c_str()) = value;
        }
        return obj.cast<CameraSettings>();
    }));
    c.def_readwrite("position", &CameraSettings::position)
        .def_readwrite("target", &CameraSettings::look_at)
        .def_readwrite("up", &CameraSettings::up)
        .def_readwrite("fov", &CameraSettings::vertical_fov_degrees)
        .def_readwrite("xmag", &CameraSettings::xmag)
        .def_readwrite("ymag", &CameraSettings::ymag)
        .def_readwrite("width", &CameraSettings::width)
        .def_readwrite("height", &CameraSettings::height)
        .def_readwrite("lens_radius", &CameraSettings::lens_radius)
        .def_readwrite("focal_distance", &CameraSettings::focal_distance)
        .def_readwrite("near_clip", &CameraSettings::near_clip)
        .def_readwrite("far_clip", &CameraSettings::far_clip);
    c.def_property(
        "size", [](const CameraSettings& s) { return py::make_tuple(s.width, s.height); },
        [](CameraSettings& s, std::pair<int, int> wh) {
            s.width = wh.first;
            s.height = wh.second;
        },
        "(width, height) in pixels");
    c.def_property(
        "projection", [](const CameraSettings& s) { return projection_name(s.projection); },
        [](CameraSettings& s, const std::string& p) {
            if (p == "perspective")
                s.projection = Projection::Perspective;
            else if (p == "orthographic")
                s.projection = Projection::Orthographic;
            else
                throw Error("projection: '" + p + "' is neither perspective nor orthographic");
        });
    c.def_property(
        "lens", [](const CameraSettings& s) { return lens_name(s.lens); },
        [](CameraSettings& s, const std::string& l) {
            if (l == "pinhole")
                s.lens = LensModel::Pinhole;
            else if (l == "thin_lens")
                s.lens = LensModel::Disk;
            else if (l == "gaussian")
                s.lens = LensModel::Gaussian;
            else
                throw Error("lens: '" + l + "' is none of pinhole, thin_lens, gaussian");
        });
    c.def_property(
        "antialias", [](const CameraSettings& s) { return s.pixel_jitter != PixelJitter::None; },
        [](CameraSettings& s, bool on) {
            s.pixel_jitter = on ? PixelJitter::Gaussian : PixelJitter::None;
        },
        "Gaussian sub-pixel jitter (rt_render's anti-aliasing); False: pixel centres");
    c.def(
        "look_at",
        [](CameraSettings& s, const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up) {
            s.position = eye;
            s.look_at = target;
            s.up = up;
            return s;
        },
        py::arg("eye"), py::arg("target"), py::arg("up") = glm::vec3(0.0f, 1.0f, 0.0f),
        "Places the camera at eye looking at target; returns the camera");
    c.def_static(
        "perspective",
        [](const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fov,
           std::pair<int, int> size) {
            CameraSettings s;
            s.pixel_jitter = PixelJitter::Gaussian;
            s.position = eye;
            s.look_at = target;
            s.up = up;
            s.vertical_fov_degrees = fov;
            s.width = size.first;
            s.height = size.second;
            return s;
        },
        py::arg("eye"), py::arg("target"), py::arg("up") = glm::vec3(0.0f, 1.0f, 0.0f),
        py::arg("fov") = 40.0f, py::arg("size") = std::pair<int, int>(640, 480));
    c.def_static(
        "orthographic",
        [](const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float xmag,
           float ymag, std::pair<int, int> size) {
            CameraSettings s;
            s.pixel_jitter = PixelJitter::Gaussian;
            s.projection = Projection::Orthographic;
            s.position = eye;
            s.look_at = target;
            s.up = up;
            s.xmag = xmag;
            s.ymag = ymag;
            s.width = size.first;
            s.height = size.second;
            return s;
        },
        py::arg("eye"), py::arg("target"), py::arg("up") = glm::vec3(0.0f, 1.0f, 0.0f),
        py::arg("xmag") = 1.0f, py::arg("ymag") = 1.0f,
        py::arg("size") = std::pair<int, int>(640, 480));
    c.def_static(
        "thin_lens",
        [](const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fov,
           float lens_radius, float focal_distance, std::pair<int, int> size) {
            CameraSettings s;
            s.pixel_jitter = PixelJitter::Gaussian;
            s.lens = LensModel::Disk;
            s.position = eye;
            s.look_at = target;
            s.up = up;
            s.vertical_fov_degrees = fov;
            s.lens_radius = lens_radius;
            s.focal_distance = focal_distance;
            s.width = size.first;
            s.height = size.second;
            return s;
        },
        py::arg("eye"), py::arg("target"), py::arg("up") = glm::vec3(0.0f, 1.0f, 0.0f),
        py::arg("fov") = 40.0f, py::arg("lens_radius") = 0.1f, py::arg("focal_distance") = 1.0f,
        py::arg("size") = std::pair<int, int>(640, 480));
    c.def(
        "validate", [](const CameraSettings& s) { (void)Camera(s); },
        "Raises librt.Error naming the first bad parameter and its value");
    c.def("__repr__", [](const CameraSettings& s) {
        return "<librt.Camera " + std::string(projection_name(s.projection)) + " " +
               std::to_string(s.width) + "x" + std::to_string(s.height) + ">";
    });
}

/// The outputs of intersect(): each name, its dtype's name and its columns (0: shape (N,)).
struct HitArray {
    const char* name;
    const char* dtype;
    py::ssize_t columns;
};
constexpr HitArray kHitArrays[] = {{"t", "float32", 0},
                                   {"primitive_id", "int64", 0},
                                   {"object_id", "int64", 0},
                                   {"instance_id", "int64", 0},
                                   {"normal", "float32", 3}};

/// An output array of intersect() for n rays: out[name] when the caller gave it (checked to
/// be a writeable C-contiguous array of the right dtype and shape: it is written in place),
/// else a new one, which the caller stores in `out` once every given array has passed.
template <typename T>
py::array_t<T> hit_array(const py::dict& out, const HitArray& a, py::ssize_t n, bool& fresh) {
    const std::vector<py::ssize_t> shape =
        a.columns == 0 ? std::vector<py::ssize_t>{n} : std::vector<py::ssize_t>{n, a.columns};
    fresh = !out.contains(a.name);
    if (fresh) return py::array_t<T>(shape);
    const py::object given = out[a.name];
    const std::string what = std::string("out['") + a.name + "']";
    const std::string wanted = std::string(a.dtype) + " array of shape (" + std::to_string(n) +
                               (a.columns == 0 ? ",)" : ", " + std::to_string(a.columns) + ")");
    if (!py::isinstance<py::array>(given))
        throw Error(what + ": expected a " + wanted + ", got a " +
                    std::string(py::str(given.get_type().attr("__name__"))));
    const auto arr = given.cast<py::array>();
    std::string shape_text = "(";
    for (py::ssize_t d = 0; d < arr.ndim(); ++d)
        shape_text += (d ? ", " : "") + std::to_string(arr.shape(d));
    shape_text += arr.ndim() == 1 ? ",)" : ")";
    if (!arr.dtype().is(py::dtype::of<T>()) || arr.ndim() != py::ssize_t(shape.size()) ||
        !std::equal(shape.begin(), shape.end(), arr.shape()))
        throw Error(what + ": expected a " + wanted + ", got " + std::string(py::str(arr.dtype())) +
                    " of shape " + shape_text);
    if (!(arr.flags() & py::array::c_style))
        throw Error(what + ": expected a C-contiguous array (np.ascontiguousarray)");
    if (!arr.writeable()) throw Error(what + ": the array is read-only");
    return py::reinterpret_borrow<py::array_t<T>>(arr);
}

/// Closest hits of N rays (Scene::intersect's GeometricHit: no surface record), the rays
/// split among threads with the GIL released, written into `out`'s arrays when it gives
/// them (no allocation) or into new ones.
py::dict intersect(PyScene& self, const py::handle& origins, const py::handle& directions,
                   float t_max, int threads, const py::object& out_arg) {
    const auto o = rows_of<float>(origins, 3, "origins");
    const auto d = rows_of<float>(directions, 3, "directions");
    if (o.shape(0) != d.shape(0))
        throw Error("intersect: origins and directions differ in length (" +
                    std::to_string(o.shape(0)) + " and " + std::to_string(d.shape(0)) + ")");
    if (threads < 0 || threads > 1024)
        throw Error("threads: " + std::to_string(threads) + " is not in [0, 1024]");
    py::dict out;
    if (!out_arg.is_none()) {
        if (!py::isinstance<py::dict>(out_arg))
            throw Error(
                "out: expected a dict of arrays (t, primitive_id, object_id, "
                "instance_id, normal), got a " +
                std::string(py::str(out_arg.get_type().attr("__name__"))));
        out = out_arg.cast<py::dict>();
        for (const auto& [key, value] : out) {
            (void)value;
            const std::string k = py::str(key);
            if (std::none_of(std::begin(kHitArrays), std::end(kHitArrays),
                             [&](const HitArray& a) { return k == a.name; }))
                throw Error("out: '" + k +
                            "' is none of t, primitive_id, object_id, instance_id, normal");
        }
    }
    self.ensure_committed();
    const auto n = static_cast<std::size_t>(o.shape(0));
    const auto ns = static_cast<py::ssize_t>(n);
    bool fresh[5];
    auto t = hit_array<float>(out, kHitArrays[0], ns, fresh[0]);
    auto prim = hit_array<std::int64_t>(out, kHitArrays[1], ns, fresh[1]);
    auto object = hit_array<std::int64_t>(out, kHitArrays[2], ns, fresh[2]);
    auto instance = hit_array<std::int64_t>(out, kHitArrays[3], ns, fresh[3]);
    auto normal = hit_array<float>(out, kHitArrays[4], ns, fresh[4]);
    const py::array arrays[5] = {t, prim, object, instance, normal};
    for (int k = 0; k < 5; ++k)
        if (fresh[k]) out[kHitArrays[k].name] = arrays[k];
    float* tp = t.mutable_data();
    std::int64_t* pp = prim.mutable_data();
    std::int64_t* op = object.mutable_data();
    std::int64_t* ip = instance.mutable_data();
    float* np = normal.mutable_data();
    const float* od = o.data();
    const float* dd = d.data();
    const Scene& scene = self.scene;
    {
        const SceneInUse in_use(self);
        py::gil_scoped_release release;
        const auto id = [](std::uint32_t v) {
            return v == kInvalidId ? std::int64_t{-1} : std::int64_t{v};
        };
        const auto work = [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                Ray ray;
                ray.origin = {od[3 * i], od[3 * i + 1], od[3 * i + 2]};
                ray.direction = {dd[3 * i], dd[3 * i + 1], dd[3 * i + 2]};
                ray.t_max = t_max;
                GeometricHit hit;
                if (scene.intersect(ray, hit)) {
                    tp[i] = hit.t;
                    pp[i] = id(hit.primitive_id);
                    op[i] = id(hit.object_id);
                    ip[i] = id(hit.instance_id);
                    for (int c = 0; c < 3; ++c)
                        np[3 * i + static_cast<std::size_t>(c)] = hit.geometric_normal[c];
                } else {
                    tp[i] = std::numeric_limits<float>::infinity();
                    pp[i] = op[i] = ip[i] = -1;
                    np[3 * i] = np[3 * i + 1] = np[3 * i + 2] = 0.0f;
                }
            }
        };
        unsigned count =
            threads > 0 ? unsigned(threads) : std::max(1u, std::thread::hardware_concurrency());
        count =
            static_cast<unsigned>(std::min<std::size_t>(count, std::max<std::size_t>(1, n / 1024)));
        std::vector<std::thread> pool;
        const std::size_t chunk = (n + count - 1) / count;
        for (unsigned k = 1; k < count; ++k)
            pool.emplace_back(work, std::min(n, k * chunk), std::min(n, (k + 1) * chunk));
        work(0, std::min(n, chunk));
        for (std::thread& th : pool) th.join();
    }
    return out;
}

std::uint32_t add_texture(PyScene& s, const py::array& texels, bool srgb) {
    if (texels.ndim() != 3 || (texels.shape(2) != 3 && texels.shape(2) != 4))
        throw Error("texture: expected an array of shape (H, W, 3) or (H, W, 4)");
    const int h = static_cast<int>(texels.shape(0));
    const int w = static_cast<int>(texels.shape(1));
    const auto channels = static_cast<std::size_t>(texels.shape(2));
    if (texels.dtype().kind() == 'u' && texels.dtype().itemsize() == 1) {
        // 8-bit texels: decoded as sRGB colour (or linear data), alpha kept.
        const auto a =
            py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(texels);
        std::vector<std::uint8_t> rgba(
            static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4, 255);
        for (std::size_t p = 0; p < rgba.size() / 4; ++p)
            for (std::size_t ch = 0; ch < channels; ++ch)
                rgba[4 * p + ch] = a.data()[channels * p + ch];
        return static_cast<std::uint32_t>(s.mutable_scene().add_texture(
            ImageTexture::from_rgba8(w, h, rgba, srgb ? ColorSpace::Srgb : ColorSpace::Linear)));
    }
    if (channels != 3) throw Error("texture: a float texture has 3 channels (linear RGB)");
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(texels);
    std::vector<glm::vec3> linear(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    std::memcpy(linear.data(), a.data(), linear.size() * sizeof(glm::vec3));
    return static_cast<std::uint32_t>(
        s.mutable_scene().add_texture(ImageTexture(w, h, std::move(linear))));
}

void bind_scene_class(py::module_& m) {
    py::class_<PyScene> c(m, "Scene", "Geometry, materials, textures and lights (librt::Scene)");
    c.def(py::init<>());
    const py::object material_type = m.attr("Material");
    c.def(
        "add_material",
        [material_type](PyScene& s, const py::object& material, const py::kwargs& kwargs) {
            if (py::isinstance<py::str>(material))
                return s.mutable_scene().add_material(
                    material_type(material, **kwargs).cast<Material>());
            if (!kwargs.empty())
                throw py::type_error("add_material: keywords go with a kind, not a Material");
            return s.mutable_scene().add_material(material.cast<Material>());
        },
        py::arg("material"), "Adds a Material, or add_material('kind', **fields); returns its id");
    c.def("add_texture", &add_texture, py::arg("texels"), py::arg("srgb") = true,
          "Adds a texture from an (H, W, 3) float array (linear RGB) or an (H, W, 3 or 4) "
          "uint8 array (sRGB unless srgb=False); returns its id");
    c.def(
        "add_sphere",
        [](PyScene& s, const glm::vec3& center, double radius, std::uint32_t material) {
            return s.mutable_scene().add_sphere(glm::dvec3(center), radius, material);
        },
        py::arg("center"), py::arg("radius"), py::arg("material"), "Returns the object id");
    c.def(
        "add_mesh",
        [](PyScene& s, const py::handle& vertices, const py::handle& indices,
           std::uint32_t material, const py::handle& normals, const py::handle& uvs) {
            return s.mutable_scene().add_mesh(mesh_from_arrays(vertices, indices, normals, uvs),
                                              material);
        },
        py::arg("vertices"), py::arg("indices"), py::arg("material"),
        py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
        "A mesh from arrays: vertices (N, 3) float, indices (M, 3) integers, optional "
        "normals (N, 3) and uvs (N, 2); returns the object id");
    c.def(
        "add_mesh_prototype",
        [](PyScene& s, const py::handle& vertices, const py::handle& indices,
           const py::handle& normals, const py::handle& uvs) {
            return s.mutable_scene().add_mesh_prototype(
                mesh_from_arrays(vertices, indices, normals, uvs));
        },
        py::arg("vertices"), py::arg("indices"), py::arg("normals") = py::none(),
        py::arg("uvs") = py::none(), "A mesh stored once, for add_instance; returns its id");
    c.def(
        "add_instance",
        [](PyScene& s, std::uint32_t prototype, const py::handle& transform,
           std::uint32_t material) {
            return s.mutable_scene().add_instance(prototype, mat4_from_array(transform), material);
        },
        py::arg("prototype"), py::arg("transform"), py::arg("material"),
        "Places a prototype by a 4 x 4 object-to-world matrix; returns the object id");
    c.def(
        "add_point_light",
        [](PyScene& s, const glm::vec3& position, const glm::vec3& intensity) {
            s.mutable_scene().add_point_light(PointLight{position, intensity});
        },
        py::arg("position"), py::arg("intensity"), "intensity in W/sr per channel");
    c.def(
        "add_sphere_light",
        [](PyScene& s, const glm::vec3& center, float radius, const glm::vec3& radiance) {
            SphereLight l;
            l.sphere = Sphere{center, radius};
            l.radiance = radiance;
            return s.mutable_scene().add_sphere_light(l);
        },
        py::arg("center"), py::arg("radius"), py::arg("radiance"));
    c.def(
        "add_quad_light",
        [](PyScene& s, const glm::vec3& corner, const glm::vec3& edge0, const glm::vec3& edge1,
           const glm::vec3& radiance, bool two_sided) {
            return s.mutable_scene().add_quad_light(
                QuadLight{corner, edge0, edge1, radiance, two_sided});
        },
        py::arg("corner"), py::arg("edge0"), py::arg("edge1"), py::arg("radiance"),
        py::arg("two_sided") = false, "Emits along edge0 x edge1");
    c.def(
        "add_disk_light",
        [](PyScene& s, const glm::vec3& center, const glm::vec3& normal, float radius,
           const glm::vec3& radiance, bool two_sided) {
            return s.mutable_scene().add_disk_light(
                DiskLight{center, normal, radius, radiance, two_sided});
        },
        py::arg("center"), py::arg("normal"), py::arg("radius"), py::arg("radiance"),
        py::arg("two_sided") = false);
    c.def(
        "add_spot_light",
        [](PyScene& s, const glm::vec3& position, const glm::vec3& direction,
           const glm::vec3& intensity, float inner_angle, float outer_angle) {
            SpotLight l;
            l.position = position;
            l.direction = direction;
            l.intensity = intensity;
            l.inner_angle = inner_angle;
            l.outer_angle = outer_angle;
            return s.mutable_scene().add_spot_light(l);
        },
        py::arg("position"), py::arg("direction"), py::arg("intensity"),
        py::arg("inner_angle") = 0.0f, py::arg("outer_angle") = 0.7853982f, "Angles in radians");
    c.def(
        "add_directional_light",
        [](PyScene& s, const glm::vec3& to_light, const glm::vec3& irradiance,
           float angular_radius) {
            DirectionalLight l;
            l.to_light = to_light;
            l.irradiance = irradiance;
            l.angular_radius = angular_radius;
            return s.mutable_scene().add_directional_light(l);
        },
        py::arg("to_light"), py::arg("irradiance"), py::arg("angular_radius") = 0.0f,
        "A sun: to_light points toward it; irradiance in W/m^2");
    c.def(
        "add_environment_light",
        [](PyScene& s, const py::object& radiance, const py::object& image, float rotate,
           float strength, bool camera_visible) {
            if (!image.is_none()) {
                const Image img = array_to_image(image, "environment image");
                EnvironmentImage env{img.width, img.height, img.pixels};
                return s.mutable_scene().add_environment_light(
                    EnvironmentLight::from_image(std::move(env), rotation_about_up(rotate),
                                                 strength),
                    camera_visible);
            }
            const glm::vec3 r =
                radiance.is_none() ? glm::vec3(1.0f) : to_vec3(radiance, "radiance");
            return s.mutable_scene().add_environment_light(EnvironmentLight::constant(r * strength),
                                                           camera_visible);
        },
        py::arg("radiance") = py::none(), py::arg("image") = py::none(), py::arg("rotate") = 0.0f,
        py::arg("strength") = 1.0f, py::arg("camera_visible") = true,
        "A constant sky of `radiance`, or an equirectangular (H, W, 3) image turned by "
        "`rotate` degrees about +y");
    c.def(
        "set_triangle_light_settings",
        [](PyScene& s, float negligible_power, float negligible_radiance) {
            s.mutable_scene().set_triangle_light_settings({negligible_power, negligible_radiance});
        },
        py::arg("negligible_power") = TriangleLightSettings{}.negligible_power,
        py::arg("negligible_radiance") = TriangleLightSettings{}.negligible_radiance,
        "Which emissive triangles commit() makes lights of: those below negligible_power of "
        "the emitters' mean power, or below negligible_radiance of their typical radiance, "
        "are left to BSDF sampling. Both 0: every emissive triangle of positive power "
        "(rt_render's --all-emitters). Un-commits the scene.");
    c.def_property_readonly(
        "triangle_light_settings",
        [](const PyScene& s) {
            const TriangleLightSettings& t = s.scene.triangle_light_settings();
            py::dict d;
            d["negligible_power"] = t.negligible_power;
            d["negligible_radiance"] = t.negligible_radiance;
            return d;
        },
        "What set_triangle_light_settings set, as a dict");
    c.def("commit", &PyScene::ensure_committed, "Builds the BVHs (render and intersect do it)");
    c.def_property_readonly("committed", [](const PyScene& s) { return s.scene.committed(); });
    c.def_property_readonly("material_count",
                            [](const PyScene& s) { return s.scene.material_count(); });
    c.def_property_readonly("object_count",
                            [](const PyScene& s) { return s.scene.object_count(); });
    c.def_property_readonly("light_count",
                            [](const PyScene& s) { return s.scene.lights().size(); });
    c.def_property_readonly(
        "warnings", [](const PyScene& s) { return s.warnings; },
        "What the loader skipped or replaced, one line each");
    c.def_property_readonly("lighting_note", [](const PyScene& s) { return s.lighting_note; });
    c.def_property_readonly(
        "bounds",
        [](PyScene& s) {
            s.ensure_committed();
            const BBox b = s.scene.bounds();
            return py::make_tuple(b.lo, b.hi);
        },
        "(min, max) corners of the geometry (commits the scene)");
    c.def("intersect", &intersect, py::arg("origins"), py::arg("directions"),
          py::arg("t_max") = std::numeric_limits<float>::infinity(), py::arg("threads") = 0,
          py::arg("out") = py::none(),
          "Closest hits of N rays (origins and directions (N, 3)): a dict of arrays t (inf: "
          "miss), primitive_id, object_id, instance_id (-1: none) and normal (N, 3), the "
          "unit geometric normal. out: a dict of such arrays (t and normal float32, the ids "
          "int64, C-contiguous, N rows) written in place, the ones it lacks added to it, and "
          "returned: pass the previous call's result to trace again without allocating. "
          "Threads share the rays; the GIL is released.");
}

}  // namespace

void bind_scene(py::module_& m) {
    bind_material(m);
    bind_camera(m);
    bind_scene_class(m);
}

}  // namespace librt::python
