// librt.Integrator: an integrator written in Python, called once per camera sample. Slow (each
// call takes the GIL, so the threads take turns): for teaching and trying ideas out, not for
// production renders (docs/python.md, "An integrator in Python").

#include "bindings.h"

#include <librt/core/error.h>
#include <librt/geometry/hit.h>
#include <librt/geometry/ray.h>
#include <librt/integrator/integrator.h>
#include <librt/material/material.h>
#include <librt/sampling/sampler.h>

#include <glm/vec2.hpp>
#include <pybind11/eval.h>

#include <limits>

namespace librt::python {

namespace {

/// What Python sees of a closest hit (Scene::intersect and the scene's shading queries).
struct PyHit {
    float t = 0.0f;
    glm::vec3 point{0.0f};
    glm::vec3 normal{0.0f};            ///< unit shading normal
    glm::vec3 geometric_normal{0.0f};  ///< unit, from the primitive's shape
    std::int64_t primitive_id = -1;
    std::int64_t object_id = -1;
    std::int64_t instance_id = -1;
    std::uint32_t material_id = 0;
    glm::vec3 albedo{0.0f};    ///< Scene::albedo: what the surface reflects (textures applied)
    glm::vec3 emission{0.0f};  ///< the material's emitted radiance
};

std::int64_t id_of(std::uint32_t v) { return v == kInvalidId ? -1 : std::int64_t{v}; }

/// The closest hit of one ray, or None. Called from a Python integrator (the GIL held).
py::object hit_of(PyScene& self, const glm::vec3& origin, const glm::vec3& direction, float t_max) {
    self.ensure_committed();
    Ray ray;
    ray.origin = origin;
    ray.direction = direction;
    ray.t_max = t_max;
    Hit hit;
    if (!self.scene.intersect(ray, hit)) return py::none();
    PyHit h;
    h.t = hit.t;
    h.point = hit.point;
    h.normal = hit.shading_normal;
    h.geometric_normal = hit.geometric_normal;
    h.primitive_id = id_of(hit.primitive_id);
    h.object_id = id_of(hit.object_id);
    h.instance_id = id_of(hit.instance_id);
    h.material_id = self.scene.material_id(hit);
    h.albedo = self.scene.albedo(hit);
    h.emission = self.scene.material(h.material_id).emission;
    return py::cast(h);
}

/// A C++ Integrator whose li() calls the Python object's li(scene, ray, sampler).
class PyIntegrator final : public Integrator {
public:
    /// The Python object (a librt.Integrator subclass) and the scene object it is given.
    PyIntegrator(py::object self, py::object scene)
        : self_(std::move(self)), scene_(std::move(scene)) {}
    ~PyIntegrator() override {
        py::gil_scoped_acquire gil;
        self_ = py::object();
        scene_ = py::object();
    }
    PyIntegrator(const PyIntegrator&) = delete;
    PyIntegrator& operator=(const PyIntegrator&) = delete;

    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& sampler) const override {
        py::gil_scoped_acquire gil;
        // The sampler lives on this worker's stack: Python gets a reference valid for the call.
        const py::object s = py::cast(&sampler, py::return_value_policy::reference);
        const py::object r = self_.attr("li")(scene_, py::cast(ray), s);
        return to_vec3(r, "Integrator.li's result");
    }

private:
    py::object self_;
    py::object scene_;
};

}  // namespace

std::unique_ptr<Integrator> python_integrator(const py::object& integrator,
                                              const py::object& scene) {
    if (!py::hasattr(integrator, "li"))
        throw Error("integrator: expected 'path', 'bdpt', 'brute' or a librt.Integrator, got " +
                    std::string(py::str(py::repr(integrator))));
    return std::make_unique<PyIntegrator>(integrator, scene);
}

void bind_integrator(py::module_& m) {
    py::class_<Ray>(m, "Ray", "A ray: origin, direction (unit for camera rays), t_min, t_max")
        .def(py::init([](const glm::vec3& o, const glm::vec3& d) {
                 Ray r;
                 r.origin = o;
                 r.direction = d;
                 return r;
             }),
             py::arg("origin"), py::arg("direction"))
        .def_readwrite("origin", &Ray::origin)
        .def_readwrite("direction", &Ray::direction)
        .def_readwrite("t_min", &Ray::t_min)
        .def_readwrite("t_max", &Ray::t_max);
    py::class_<Sampler>(m, "Sampler",
                        "The random numbers of one camera sample (valid during Integrator.li)")
        .def("next_1d", &Sampler::next_1d, "The next number in [0, 1)")
        .def(
            "next_2d",
            [](Sampler& s) {
                const glm::vec2 u = s.next_2d();
                return py::make_tuple(u.x, u.y);
            },
            "The next point in [0, 1)^2");
    py::class_<PyHit>(m, "Hit", "A closest hit (Scene.hit)")
        .def_readonly("t", &PyHit::t)
        .def_readonly("point", &PyHit::point)
        .def_readonly("normal", &PyHit::normal)
        .def_readonly("geometric_normal", &PyHit::geometric_normal)
        .def_readonly("primitive_id", &PyHit::primitive_id)
        .def_readonly("object_id", &PyHit::object_id)
        .def_readonly("instance_id", &PyHit::instance_id)
        .def_readonly("material_id", &PyHit::material_id)
        .def_readonly("albedo", &PyHit::albedo)
        .def_readonly("emission", &PyHit::emission);
    py::reinterpret_borrow<py::class_<PyScene>>(m.attr("Scene"))
        .def("hit", &hit_of, py::arg("origin"), py::arg("direction"),
             py::arg("t_max") = std::numeric_limits<float>::infinity(),
             "The closest hit of one ray (a librt.Hit), or None");
    // A plain Python base class: subclasses define li(self, scene, ray, sampler) -> (r, g, b).
    py::exec(R"(
class Integrator:
    """An integrator written in Python: subclass it and define li(self, scene, ray, sampler),
    returning the radiance (r, g, b) along the camera ray. librt.render(..., integrator=obj)
    calls it once per sample, taking the GIL each time: slow (threads take turns), for
    teaching. Use scene.hit(origin, direction) and sampler.next_1d() / next_2d()."""

    def li(self, scene, ray, sampler):
        raise NotImplementedError("define li(self, scene, ray, sampler) in a subclass")
)",
             m.attr("__dict__"));
    m.attr("Integrator").attr("__module__") = "librt";
}

}  // namespace librt::python
