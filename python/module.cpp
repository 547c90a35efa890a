// The Python module `librt` (pybind11): its version, its exception and the parts bound in
// the other files of this folder. docs/python.md describes the API.

#include "bindings.h"

#include <librt/core/error.h>

namespace librt::python {

glm::vec3 to_vec3(const py::handle& value, const char* what) {
    try {
        const py::sequence s = py::reinterpret_borrow<py::sequence>(value);
        if (!py::isinstance<py::sequence>(value) || py::len(s) != 3) throw py::cast_error();
        return {s[0].cast<float>(), s[1].cast<float>(), s[2].cast<float>()};
    } catch (const py::cast_error&) {
        throw Error(std::string(what) + ": expected three numbers, got " +
                    std::string(py::str(py::repr(value))));
    }
}

namespace {
py::handle g_cancelled;  // set once at import; the module keeps the type alive
}  // namespace

py::handle cancelled_type() { return g_cancelled; }

}  // namespace librt::python

namespace {
struct CancelledTag {};  // only names the Python type; never thrown
}  // namespace

PYBIND11_MODULE(librt, m) {
    namespace py = pybind11;
    using namespace librt::python;
    m.doc() = "librt, a physically based CPU ray tracer, from Python (docs/python.md)";
    m.attr("__version__") = LIBRT_PY_VERSION;
    // librt::Error becomes librt.Error (a RuntimeError), its message naming the file and
    // line, the JSON path, or the parameter and value, as in the apps.
    static py::exception<librt::Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<CancelledTag> cancelled(m, "Cancelled", error.ptr());
    g_cancelled = cancelled;
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const librt::Error& e) {
            error(e.what());
        }
    });
    bind_scene(m);
    bind_render(m);
    bind_images(m);
    bind_integrator(m);
}
