#pragma once

// Helpers shared by the OBJ and MTL bad-input tests: the smallest OBJ vertex list and a
// load that collects the warnings.

#include <librt/geometry/mesh.h>
#include <librt/obj/obj.h>

#include <filesystem>
#include <string>
#include <vector>

namespace librt::testing {

/// Three vertices of one triangle, to which a test appends its faces.
inline const std::string kObjTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

/// load_obj of `p` with its warnings collected into `warnings`.
inline TriangleMesh load_with_warnings(const std::filesystem::path& p,
                                       std::vector<std::string>& warnings) {
    ObjLoadOptions options;
    options.warnings = &warnings;
    return load_obj(p, options);
}

}  // namespace librt::testing
