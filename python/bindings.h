#pragma once

// Shared between the binding files of the Python module `librt` (docs/python.md). Only
// librt's public API (librt/include/librt/...) is used here.

#include <librt/core/image.h>
#include <librt/film/camera.h>
#include <librt/integrator/integrator.h>
#include <librt/scene/scene.h>

#include <glm/vec3.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

namespace librt::python {

namespace py = pybind11;

/// A scene as Python holds it: the Scene plus what loading it reported.
struct PyScene {
    Scene scene;
    std::vector<std::string> warnings;  ///< the loader's warnings, one line each
    std::string lighting_note;          ///< the studio lighting added, or empty
    /// Renders and queries running on it with the GIL released (changed with the GIL held).
    int in_use = 0;
    /// The scene committed (BVHs built) if it is not: what render() and intersect() need.
    /// The BVH build runs without the GIL.
    void ensure_committed();
    /// The scene itself, to change: throws librt::Error while a render or query reads it
    /// (from another Python thread, or from a progress callback).
    Scene& mutable_scene();
};

/// Marks a scene in use while the GIL is released around a render or query of it.
class SceneInUse {
public:
    explicit SceneInUse(PyScene& s) : s_(s) { ++s_.in_use; }
    ~SceneInUse() { --s_.in_use; }  // runs with the GIL held again
    SceneInUse(const SceneInUse&) = delete;
    SceneInUse& operator=(const SceneInUse&) = delete;

private:
    PyScene& s_;
};

/// A float32 H x W x 3 NumPy array viewing `image` without a copy: the array owns the
/// image through a capsule, freed when the last view of it goes.
py::array_t<float> image_to_array(Image image);
/// An image copied from a float H x W x 3 (or H x W, grey) array; throws librt::Error
/// naming `what` for any other shape or a non-finite value.
Image array_to_image(const py::array& array, const char* what);
/// A float32 H x W array owning `values` (width * height of them) without a copy.
py::array_t<float> plane_to_array(std::vector<float> values, int width, int height);

/// librt.Cancelled (a librt.Error): a render stopped by its progress callback.
py::handle cancelled_type();

/// A vec3 from any sequence of three numbers; throws librt::Error naming `what` otherwise.
glm::vec3 to_vec3(const py::handle& value, const char* what);

void bind_scene(py::module_& m);       // scene_bindings.cpp: scenes, materials, lights, cameras
void bind_render(py::module_& m);      // render_bindings.cpp: load, render
void bind_images(py::module_& m);      // image_bindings.cpp: read, write, tone map
void bind_integrator(py::module_& m);  // integrator_bindings.cpp: Integrator, Ray, Hit, Sampler

/// The C++ integrator calling a librt.Integrator subclass's li (the GIL taken per call).
std::unique_ptr<Integrator> python_integrator(const py::object& integrator,
                                              const py::object& scene);

}  // namespace librt::python

// glm vectors and matrices as Python sequences and NumPy arrays: a vec3 from any three
// numbers (a tuple, a list, an array), returned as a tuple; a mat4 from a 4 x 4 array in
// the usual row-major mathematical layout (m[row][col], translation in the last column).
namespace pybind11::detail {

template <>
struct type_caster<glm::vec3> {
    PYBIND11_TYPE_CASTER(glm::vec3, const_name("tuple[float, float, float]"));
    bool load(handle src, bool convert) {
        if (!isinstance<sequence>(src) || isinstance<str>(src)) return false;
        const auto s = reinterpret_borrow<sequence>(src);
        if (len(s) != 3) return false;
        for (int i = 0; i < 3; ++i) {
            make_caster<float> c;
            if (!c.load(s[static_cast<std::size_t>(i)], convert)) return false;
            value[i] = cast_op<float>(c);
        }
        return true;
    }
    static handle cast(const glm::vec3& v, return_value_policy, handle) {
        return make_tuple(v.x, v.y, v.z).release();
    }
};

}  // namespace pybind11::detail
