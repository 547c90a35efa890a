// load_obj, in steps: the file read (read_obj_text), a strict pre-pass (obj_scan), tinyobjloader
// (read_with_tinyobj), the MTL files (load_materials), then faces checked, triangulated
// (obj_polygon) and their corners unified into vertices (obj_vertices) by add_faces, and the
// vertices' uvs and normals (add_vertex_attributes). save_obj is in obj_save.cpp.

#include "io/file_io.h"
#include "obj/obj_mtl.h"
#include "obj/obj_polygon.h"
#include "obj/obj_scan.h"
#include "obj/obj_vertices.h"

#include <librt/core/error.h>
#include <librt/obj/obj.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <istream>
#include <limits>
#include <streambuf>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <vector>

namespace librt {

namespace {

namespace fs = std::filesystem;

constexpr std::size_t npos = std::string::npos;

// ---------------------------------------------------------------------------------------------
// Loading

/// An MTL file is text of a few lines per material: 256 MiB is far beyond any real one.
constexpr std::uint64_t kMaxMtlBytes = std::uint64_t{256} << 20;

/// A read-only stream buffer over text that lives elsewhere (no copy, unlike stringbuf).
class ViewBuffer : public std::streambuf {
public:
    explicit ViewBuffer(std::string_view text) {
        char* begin = const_cast<char*>(text.data());  // never written: get area only
        setg(begin, begin, begin + text.size());
    }
};

/// tinyobjloader's newline-separated messages as trimmed, non-empty lines.
std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        const auto first = line.find_first_not_of(" \t\r.");
        const auto last = line.find_last_not_of(" \t\r");
        if (first != std::string::npos) lines.push_back(line.substr(first, last - first + 1));
        start = end + 1;
    }
    return lines;
}

using detail::Corner;
using detail::kAbsent;
using detail::Polygon;
using detail::PolygonScratch;
using detail::triangulate_polygon;
using detail::VertexUnifier;

/// "" when the corner's indices are in range, else what is wrong with them.
std::string check_corner(const Corner& c, std::size_t nv, std::size_t nvt, std::size_t nvn) {
    // tinyobjloader made indices 0-based (relative ones resolved), so +1 is the file's value.
    if (c.v < 0) return "a relative position index points before the first position";
    if (static_cast<std::size_t>(c.v) >= nv) {
        return "position index " + std::to_string(c.v + 1) + " is out of range (" +
               std::to_string(nv) + " positions)";
    }
    if (c.vt < kAbsent || (c.vt >= 0 && static_cast<std::size_t>(c.vt) >= nvt)) {
        return "texture coordinate index " + std::to_string(c.vt + 1) + " is out of range (" +
               std::to_string(nvt) + " texture coordinates)";
    }
    if (c.vn < kAbsent || (c.vn >= 0 && static_cast<std::size_t>(c.vn) >= nvn)) {
        return "normal index " + std::to_string(c.vn + 1) + " is out of range (" +
               std::to_string(nvn) + " normals)";
    }
    return "";
}

glm::vec3 to_vec3(const tinyobj::real_t* v) { return {v[0], v[1], v[2]}; }

/// Fills normals of vertices without a vn with the area-weighted normal of their triangles.
void fill_missing_normals(TriangleMesh& mesh, const std::vector<std::int32_t>& vn) {
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec3 n =
            area_normal(Triangle{mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]});
        for (int k = 0; k < 3; ++k) {
            if (vn[t[k]] == kAbsent) mesh.normals[t[k]] += n;
        }
    }
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        const float len = glm::length(mesh.normals[i]);
        if (vn[i] == kAbsent && len > 0.0f) mesh.normals[i] /= len;
    }
}

/// Hands warnings to the caller; with no list given, the caller does not want them (the
/// library never prints).
void report(const fs::path& path, const std::vector<std::string>& lines,
            const ObjLoadOptions& options) {
    if (options.warnings == nullptr) return;
    for (const std::string& line : lines)
        options.warnings->push_back(printable(path.string() + ": " + line, kMaxErrorBytes));
}

/// Reads the MTL files the OBJ names (mtllib, resolved against the OBJ's directory),
/// appending their materials. A missing file is a warning (its materials are then unknown
/// and their faces get the default material); anything else wrong is an Error.
void load_mtllibs(const detail::ObjScanResult& scan, const fs::path& obj_path, bool allow_outside,
                  std::vector<MeshMaterial>& materials, std::vector<std::string>& warnings,
                  std::vector<std::string>& file_warnings, std::vector<FileRead>* files_read) {
    const fs::path dir = obj_path.parent_path();
    const std::string lift =
        " (an OBJ reads only files in its own directory tree; "
        "ObjLoadOptions::allow_outside_files, rt_render --allow-outside-files, lifts this "
        "for a file you trust)";
    std::vector<std::string> seen;
    for (const auto& [rest, line] : scan.mtllibs) {
        // mtllib takes several files separated by spaces, but a single name may contain
        // spaces too: the whole rest of the line is tried first when it names a file.
        const std::string whole = detail::normalise_separators(rest);
        std::vector<std::string> names;
        std::error_code ec;
        if (!whole.empty() && fs::exists(dir / whole, ec)) {
            names.push_back(whole);
        } else {
            std::size_t start = 0;
            while (start < whole.size()) {
                const std::size_t end = std::min(whole.find_first_of(" \t", start), whole.size());
                if (end > start) names.push_back(whole.substr(start, end - start));
                start = end + 1;
            }
        }
        if (names.empty()) {
            warnings.push_back("line " + std::to_string(line) + ": mtllib without a file name");
        }
        for (const std::string& name : names) {
            if (std::find(seen.begin(), seen.end(), name) != seen.end()) continue;
            seen.push_back(name);
            const fs::path mtl_path = dir / name;
            if (!allow_outside && !detail::resolve_in_tree(dir, name).inside)
                throw Error(obj_path.string() + ":" + std::to_string(line) + ": mtllib " +
                            quote_untrusted(name) + " leads outside the OBJ's directory" + lift);
            if (!fs::exists(fs::symlink_status(mtl_path, ec)) || !fs::exists(mtl_path, ec)) {
                warnings.push_back("line " + std::to_string(line) + ": MTL file " +
                                   quote_untrusted(mtl_path.string()) +
                                   " not found: its materials' faces get the default material");
                continue;
            }
            detail::ReadRequest request;
            request.what = "an MTL file";
            request.max_bytes = kMaxMtlBytes;
            const std::string text = detail::read_regular_file(mtl_path, request);
            if (files_read != nullptr) files_read->push_back({mtl_path, digest_of(text)});
            const std::size_t first = materials.size();
            detail::parse_mtl(text, mtl_path.string(), materials, file_warnings);
            // map_Kd is relative to the MTL's directory, which is the OBJ's.
            for (std::size_t i = first; i < materials.size(); ++i) {
                std::string& tex = materials[i].diffuse_texture;
                if (tex.empty()) continue;
                if (!allow_outside && !detail::resolve_in_tree(dir, tex).inside)
                    throw Error(mtl_path.string() + ": material " +
                                quote_untrusted(materials[i].name) + ": map_Kd " +
                                quote_untrusted(tex) + " leads outside the OBJ's directory" + lift);
                tex = (dir / tex).lexically_normal().string();
            }
        }
    }
}

/// The OBJ's text: a regular file only (a FIFO would block, /dev/zero never end), within the
/// size limit, and refused by its first 64 KiB when those are binary (a 2 GB sparse file of
/// zeros is refused at once, not after reading it all).
std::string read_obj_text(const fs::path& path, const ObjLoadOptions& options) {
    detail::ReadRequest request;
    request.what = "an OBJ file";
    request.max_bytes = options.max_file_bytes;
    request.raise_hint = "raise ObjLoadOptions::max_file_bytes to read it";
    request.check_head = [&](std::string_view head) {
        detail::check_obj_head(head, path.string());
    };
    return detail::read_regular_file(path, request);
}

/// Our own strict pass, before tinyobjloader: it names the line of what tinyobjloader would
/// misread silently (bad numbers, bad indices, binary data). Trailing comments it accepted
/// would make tinyobjloader fail on `f 1 2 3 # c`: they are blanked in `text` (in place, no
/// copy of the file).
detail::ObjScanResult scan_and_blank_comments(std::string& text, const fs::path& path,
                                              const ObjLoadOptions& options) {
    detail::ObjScanOptions scan_options;
    scan_options.check_uv_indices = options.load_uvs;
    scan_options.check_normal_indices = options.load_normals;
    detail::ObjScanResult scan = detail::scan_obj(text, path.string(), scan_options);
    for (const std::size_t at : scan.trailing_comments) {
        for (std::size_t i = at; i < text.size() && text[i] != '\n' && text[i] != '\r'; ++i) {
            text[i] = ' ';
        }
    }
    return scan;
}

/// What tinyobjloader read: the file's attributes and faces, and the messages of its we
/// keep (in the form of our other warnings).
struct TinyObjRead {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<std::string> messages;
};

/// Runs tinyobjloader on the scanned text. We triangulate ourselves (triangulate = false):
/// tinyobjloader's triangulation reads positions through unchecked indices (n-gons) or
/// silently drops faces with bad ones (quads), before we could check them. No vertex
/// colours. No material reader either: tinyobjloader cuts usemtl names at the first space
/// and reads MTL numbers leniently, so the MTL files and the usemtl switches come from our
/// own reader and scan. Throws Error with its error lines when it fails.
TinyObjRead read_with_tinyobj(const std::string& text, const detail::ObjScanResult& scan,
                              const fs::path& path) {
    ViewBuffer buffer(std::string_view(text).substr(scan.skip));
    std::istream stream(&buffer);
    TinyObjRead read;
    std::vector<tinyobj::material_t> unused_materials;
    std::string tiny_warning, tiny_error;
    if (!tinyobj::LoadObj(&read.attrib, &read.shapes, &unused_materials, &tiny_warning, &tiny_error,
                          &stream,
                          /*readMatFn=*/nullptr, /*triangulate=*/false,
                          /*default_vcols_fallback=*/false)) {
        const std::vector<std::string> lines = split_lines(tiny_error);
        std::string message = path.string() + ":";
        for (const std::string& line : lines) message += " " + line;
        if (lines.empty()) message += " cannot parse";
        throw Error(message);
    }
    for (std::string& line : split_lines(tiny_warning)) {
        // The scan reported these, with their line numbers (short faces, bad indices), or
        // they concern materials, which tinyobjloader does not read here.
        if (line == "Degenerated face found" || line.find("indices out of bounds") != npos ||
            line.rfind("material [", 0) == 0) {
            continue;
        }
        // "Empty group name. line: N" in the form of our other warnings.
        if (const std::size_t at = line.rfind("Empty group name. line: ", 0); at == 0) {
            read.messages.push_back("line " + line.substr(24) + ": 'g' without a name");
            continue;
        }
        read.messages.push_back(std::move(line));
    }
    for (std::string& line : split_lines(tiny_error)) read.messages.push_back(std::move(line));
    return read;
}

/// The OBJ's materials and which one each usemtl name selects.
struct ObjMaterials {
    std::vector<MeshMaterial> materials;    ///< the MTL files' materials, in mtllib order
    std::vector<std::string> mtl_warnings;  ///< already "mtl_path:line: ..."
    /// Per usemtl name (scan.material_names): its material, or default_material.
    std::vector<std::uint32_t> by_name;
    std::uint32_t default_material = 0;  ///< one past the MTL files' materials
};

/// Loads the MTL files and resolves the usemtl names against them, where the first
/// definition of a name wins. A name no MTL file defines gets the default material, warned
/// about once (at its first use) in `warnings`.
ObjMaterials load_materials(const detail::ObjScanResult& scan, const fs::path& path,
                            const ObjLoadOptions& options, std::vector<std::string>& warnings) {
    ObjMaterials m;
    load_mtllibs(scan, path, options.allow_outside_files, m.materials, warnings, m.mtl_warnings,
                 options.files_read);
    std::unordered_map<std::string, std::uint32_t> material_index;
    for (std::size_t i = 0; i < m.materials.size(); ++i) {
        material_index.try_emplace(m.materials[i].name, static_cast<std::uint32_t>(i));
    }
    m.default_material = static_cast<std::uint32_t>(m.materials.size());
    m.by_name.assign(scan.material_names.size(), m.default_material);
    for (std::size_t i = 0; i < scan.material_names.size(); ++i) {
        const auto& [name, line] = scan.material_names[i];
        const auto it = material_index.find(name);
        if (it != material_index.end()) {
            m.by_name[i] = it->second;
        } else {
            warnings.push_back("line " + std::to_string(line) + ": usemtl " +
                               quote_untrusted(name) +
                               ": no such material in the MTL file(s); its faces get the "
                               "default material");
        }
    }
    return m;
}

/// The exact triangle count of the faces (a polygon of n corners makes n - 2 triangles), for
/// reserving. Throws Error for a face of 256+ corners: num_face_vertices is a byte, and such
/// a face has wrapped around.
std::size_t count_triangles(const std::vector<tinyobj::shape_t>& shapes, const fs::path& path) {
    std::size_t triangles = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        std::size_t corner_count = 0;
        for (const unsigned char n : shape.mesh.num_face_vertices) {
            corner_count += n;
            triangles += n >= 3 ? n - 2u : 0u;
        }
        if (corner_count != shape.mesh.indices.size()) {
            throw Error(path.string() + ": a face in " + quote_untrusted(shape.name) +
                        " has more than 255 corners (not supported)");
        }
    }
    return triangles;
}

/// What add_faces met besides triangles.
struct FaceTally {
    std::size_t faces = 0;             ///< every face, short ones too (the scan counts the same)
    std::size_t zero_area = 0;         ///< polygons that triangulate to nothing, skipped
    std::size_t not_simple = 0;        ///< polygons overlapping themselves, skipped
    std::size_t first_not_simple = 0;  ///< 1-based face number of the first, 0 = none
    bool uses_default = false;         ///< a triangle has the default material
};

/// Checks each face's corners (Error "path: face N: ..."), unifies them into `mesh`'s
/// vertices, triangulates the polygons and gives each triangle the material of the usemtl
/// switch in force.
FaceTally add_faces(const TinyObjRead& read, const detail::ObjScanResult& scan,
                    const ObjMaterials& materials, const fs::path& path,
                    const ObjLoadOptions& options, VertexUnifier& unifier, TriangleMesh& mesh) {
    const std::size_t nv = read.attrib.vertices.size() / 3;
    const std::size_t nvt = read.attrib.texcoords.size() / 2;
    const std::size_t nvn = read.attrib.normals.size() / 3;
    FaceTally tally;
    std::size_t run = 0;  // the usemtl switch in force (scan.material_runs)
    std::vector<std::uint32_t> corners;
    PolygonScratch scratch;
    for (const tinyobj::shape_t& shape : read.shapes) {
        const tinyobj::mesh_t& m = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
            const std::size_t face_number = ++tally.faces;  // 1-based in file order
            const std::size_t n = m.num_face_vertices[f];
            corners.clear();
            for (std::size_t k = 0; k < n; ++k) {
                const tinyobj::index_t& idx = m.indices[offset + k];
                const Corner c{idx.vertex_index, options.load_uvs ? idx.texcoord_index : kAbsent,
                               options.load_normals ? idx.normal_index : kAbsent};
                if (const std::string problem = check_corner(c, nv, nvt, nvn); !problem.empty()) {
                    throw Error(path.string() + ": face " + std::to_string(face_number) + ": " +
                                problem);
                }
                corners.push_back(unifier.vertex(c));
            }
            offset += n;
            if (n < 3) continue;  // tinyobjloader already warned

            // Faces of 3+ corners come in file order, as the scan counted them.
            const std::size_t face_index = face_number - 1;
            while (run < scan.material_runs.size() &&
                   scan.material_runs[run].first_face <= face_index) {
                ++run;
            }
            const std::uint32_t material =
                run == 0 ? materials.default_material
                         : materials.by_name[scan.material_runs[run - 1].name];

            const std::size_t before = mesh.triangles.size();
            if (n == 3) {
                mesh.triangles.emplace_back(corners[0], corners[1], corners[2]);
            } else if (const Polygon p =
                           triangulate_polygon(mesh.positions, corners, scratch, mesh.triangles);
                       p != Polygon::Triangulated) {
                ++(p == Polygon::ZeroArea ? tally.zero_area : tally.not_simple);
                if (p == Polygon::NotSimple && tally.first_not_simple == 0)
                    tally.first_not_simple = face_number;
                continue;
            }
            tally.uses_default = tally.uses_default || material == materials.default_material;
            mesh.material_ids.insert(mesh.material_ids.end(), mesh.triangles.size() - before,
                                     material);
        }
    }
    return tally;
}

/// The warnings about the polygons add_faces skipped.
void warn_skipped(const FaceTally& tally, std::vector<std::string>& warnings) {
    if (tally.zero_area > 0) {
        warnings.push_back(std::to_string(tally.zero_area) +
                           " polygon(s) of zero area triangulate to nothing and were skipped");
    }
    if (tally.not_simple > 0) {
        warnings.push_back(std::to_string(tally.not_simple) +
                           " polygon(s) overlapping themselves (first: face " +
                           std::to_string(tally.first_not_simple) +
                           ") have no triangulation of the same area and were skipped");
    }
}

/// The unified vertices' texture coordinates and normals, when any corner had one; a
/// vertex without a normal gets its triangles' area-weighted normal.
void add_vertex_attributes(const tinyobj::attrib_t& attrib, const VertexUnifier& unifier,
                           TriangleMesh& mesh) {
    const std::vector<std::int32_t>& vt = unifier.vt();
    const std::vector<std::int32_t>& vn = unifier.vn();
    const bool any_vt = std::any_of(vt.begin(), vt.end(), [](std::int32_t i) { return i >= 0; });
    const bool any_vn = std::any_of(vn.begin(), vn.end(), [](std::int32_t i) { return i >= 0; });
    if (any_vt) {
        mesh.uvs.assign(mesh.positions.size(), glm::vec2(0.0f));
        for (std::size_t i = 0; i < vt.size(); ++i) {
            if (vt[i] >= 0) {
                const auto j = static_cast<std::size_t>(vt[i]);
                mesh.uvs[i] = {attrib.texcoords[2 * j], attrib.texcoords[2 * j + 1]};
            }
        }
    }
    if (any_vn) {
        mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
        bool missing = false;
        for (std::size_t i = 0; i < vn.size(); ++i) {
            if (vn[i] >= 0) {
                mesh.normals[i] = to_vec3(&attrib.normals[3 * static_cast<std::size_t>(vn[i])]);
            } else {
                missing = true;
            }
        }
        if (missing) fill_missing_normals(mesh, vn);
    }
}

}  // namespace

TriangleMesh load_obj(const fs::path& path, const ObjLoadOptions& options) {
    std::string text = read_obj_text(path, options);
    // The digest before the scan blanks comments in `text`: of the bytes as in the file.
    if (options.files_read != nullptr) options.files_read->push_back({path, digest_of(text)});
    detail::ObjScanResult scan = scan_and_blank_comments(text, path, options);
    const TinyObjRead read = read_with_tinyobj(text, scan, path);
    std::vector<std::string> warnings = std::move(scan.warnings);
    warnings.insert(warnings.end(), read.messages.begin(), read.messages.end());
    ObjMaterials materials = load_materials(scan, path, options, warnings);

    const std::size_t nv = read.attrib.vertices.size() / 3;
    if (nv >= std::numeric_limits<std::uint32_t>::max()) {
        throw Error(path.string() + ": too many positions (" + std::to_string(nv) + ")");
    }
    const std::size_t triangle_count = count_triangles(read.shapes, path);
    TriangleMesh mesh;
    mesh.triangles.reserve(triangle_count);
    mesh.material_ids.reserve(triangle_count);
    mesh.positions.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) mesh.positions[i] = to_vec3(&read.attrib.vertices[3 * i]);
    VertexUnifier unifier(mesh.positions);
    const FaceTally tally = add_faces(read, scan, materials, path, options, unifier, mesh);
    if (tally.faces != scan.face_count) {
        // The usemtl switches are counted in the scan's faces: the two must agree.
        throw Error(path.string() + ": internal error: tinyobjloader read " +
                    std::to_string(tally.faces) + " faces, the scan " +
                    std::to_string(scan.face_count));
    }
    warn_skipped(tally, warnings);
    mesh.materials = std::move(materials.materials);
    if (tally.uses_default) {
        MeshMaterial fallback;
        fallback.name = "default";
        mesh.materials.push_back(fallback);
    }
    add_vertex_attributes(read.attrib, unifier, mesh);

    report(path, warnings, options);
    if (options.warnings != nullptr) {
        for (std::string& w : materials.mtl_warnings)
            options.warnings->push_back(printable(w, kMaxErrorBytes));
    }
    try {
        if (options.transform != glm::mat4(1.0f)) transform(mesh, options.transform);
        validate(mesh);
    } catch (const Error& e) {
        throw Error(path.string() + ": " + e.what());
    }
    return mesh;
}

}  // namespace librt
