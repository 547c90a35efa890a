// load_obj: a strict pre-pass (obj_scan), tinyobjloader, then faces checked, triangulated
// (obj_polygon) and their corners unified into vertices (obj_vertices). save_obj is in
// obj_save.cpp.

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
                  std::vector<std::string>& file_warnings) {
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
                warnings.push_back("line " + std::to_string(line) + ": MTL file '" +
                                   mtl_path.string() +
                                   "' not found: its materials' faces get the default material");
                continue;
            }
            detail::ReadRequest request;
            request.what = "an MTL file";
            request.max_bytes = kMaxMtlBytes;
            const std::string text = detail::read_regular_file(mtl_path, request);
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

}  // namespace

TriangleMesh load_obj(const fs::path& path, const ObjLoadOptions& options) {
    // A regular file only (a FIFO would block, /dev/zero never end), within the size limit,
    // and refused by its first 64 KiB when those are binary (a 2 GB sparse file of zeros
    // is refused at once, not after reading it all).
    detail::ReadRequest request;
    request.what = "an OBJ file";
    request.max_bytes = options.max_file_bytes;
    request.raise_hint = "raise ObjLoadOptions::max_file_bytes to read it";
    request.check_head = [&](std::string_view head) {
        detail::check_obj_head(head, path.string());
    };
    std::string text = detail::read_regular_file(path, request);
    const fs::path dir = path.parent_path();

    // Our own strict pass first: it names the line of what tinyobjloader would misread
    // silently (bad numbers, bad indices, binary data).
    detail::ObjScanOptions scan_options;
    scan_options.check_uv_indices = options.load_uvs;
    scan_options.check_normal_indices = options.load_normals;
    detail::ObjScanResult scan = detail::scan_obj(text, path.string(), scan_options);
    // Trailing comments the scan accepted would make tinyobjloader fail on `f 1 2 3 # c`:
    // blank them (in place, no copy of the file).
    for (const std::size_t at : scan.trailing_comments) {
        for (std::size_t i = at; i < text.size() && text[i] != '\n' && text[i] != '\r'; ++i) {
            text[i] = ' ';
        }
    }

    // We triangulate ourselves (triangulate = false): tinyobjloader's triangulation reads
    // positions through unchecked indices (n-gons) or silently drops faces with bad ones
    // (quads), before we could check them. No vertex colours. No material reader either:
    // tinyobjloader cuts usemtl names at the first space and reads MTL numbers leniently, so
    // the MTL files and the usemtl switches come from our own reader and scan.
    ViewBuffer buffer(std::string_view(text).substr(scan.skip));
    std::istream stream(&buffer);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> unused_materials;
    std::string tiny_warning, tiny_error;
    if (!tinyobj::LoadObj(&attrib, &shapes, &unused_materials, &tiny_warning, &tiny_error, &stream,
                          /*readMatFn=*/nullptr, /*triangulate=*/false,
                          /*default_vcols_fallback=*/false)) {
        const std::vector<std::string> lines = split_lines(tiny_error);
        std::string message = path.string() + ":";
        for (const std::string& line : lines) message += " " + line;
        if (lines.empty()) message += " cannot parse";
        throw Error(message);
    }
    std::vector<std::string> warnings = std::move(scan.warnings);
    for (std::string& line : split_lines(tiny_warning)) {
        // The scan reported these, with their line numbers (short faces, bad indices), or
        // they concern materials, which tinyobjloader does not read here.
        if (line == "Degenerated face found" || line.find("indices out of bounds") != npos ||
            line.rfind("material [", 0) == 0) {
            continue;
        }
        // "Empty group name. line: N" in the form of our other warnings.
        if (const std::size_t at = line.rfind("Empty group name. line: ", 0); at == 0) {
            warnings.push_back("line " + line.substr(24) + ": 'g' without a name");
            continue;
        }
        warnings.push_back(std::move(line));
    }
    for (std::string& line : split_lines(tiny_error)) warnings.push_back(std::move(line));

    // Materials: the MTL files in mtllib order, then a name -> index map where the first
    // definition of a name wins.
    std::vector<MeshMaterial> materials;
    std::vector<std::string> mtl_warnings;  // already "mtl_path:line: ..."
    load_mtllibs(scan, path, options.allow_outside_files, materials, warnings, mtl_warnings);
    std::unordered_map<std::string, std::uint32_t> material_index;
    for (std::size_t i = 0; i < materials.size(); ++i) {
        material_index.try_emplace(materials[i].name, static_cast<std::uint32_t>(i));
    }
    const auto default_material = static_cast<std::uint32_t>(materials.size());
    // Per usemtl name: its material, or the default (warned about once, at its first use).
    std::vector<std::uint32_t> name_material(scan.material_names.size(), default_material);
    for (std::size_t i = 0; i < scan.material_names.size(); ++i) {
        const auto& [name, line] = scan.material_names[i];
        const auto it = material_index.find(name);
        if (it != material_index.end()) {
            name_material[i] = it->second;
        } else {
            warnings.push_back("line " + std::to_string(line) + ": usemtl '" + name +
                               "': no such material in the MTL file(s); its faces get the "
                               "default material");
        }
    }

    const std::size_t nv = attrib.vertices.size() / 3;
    const std::size_t nvt = attrib.texcoords.size() / 2;
    const std::size_t nvn = attrib.normals.size() / 3;
    if (nv >= std::numeric_limits<std::uint32_t>::max()) {
        throw Error(path.string() + ": too many positions (" + std::to_string(nv) + ")");
    }

    // Reserve the exact triangle count: a polygon of n corners makes n - 2 triangles.
    std::size_t triangle_estimate = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        std::size_t corner_count = 0;
        for (const unsigned char n : shape.mesh.num_face_vertices) {
            corner_count += n;
            triangle_estimate += n >= 3 ? n - 2u : 0u;
        }
        // num_face_vertices is a byte: a face of 256+ corners has wrapped around.
        if (corner_count != shape.mesh.indices.size()) {
            throw Error(path.string() + ": a face in '" + shape.name +
                        "' has more than 255 corners (not supported)");
        }
    }

    TriangleMesh mesh;
    mesh.triangles.reserve(triangle_estimate);
    mesh.material_ids.reserve(triangle_estimate);
    mesh.positions.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) mesh.positions[i] = to_vec3(&attrib.vertices[3 * i]);
    VertexUnifier unifier(mesh.positions);

    bool uses_default = false;
    std::size_t run = 0;  // the usemtl switch in force (scan.material_runs)
    std::size_t skipped = 0, not_simple = 0;
    std::size_t face_number = 0;  // 1-based in file order, for messages
    std::size_t not_simple_face = 0;
    std::vector<std::uint32_t> corners;
    PolygonScratch scratch;

    for (const tinyobj::shape_t& shape : shapes) {
        const tinyobj::mesh_t& m = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
            ++face_number;
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
                run == 0 ? default_material : name_material[scan.material_runs[run - 1].name];

            const std::size_t before = mesh.triangles.size();
            if (n == 3) {
                mesh.triangles.emplace_back(corners[0], corners[1], corners[2]);
            } else if (const Polygon p =
                           triangulate_polygon(mesh.positions, corners, scratch, mesh.triangles);
                       p != Polygon::Triangulated) {
                ++(p == Polygon::ZeroArea ? skipped : not_simple);
                if (p == Polygon::NotSimple && not_simple_face == 0) not_simple_face = face_number;
                continue;
            }
            uses_default = uses_default || material == default_material;
            mesh.material_ids.insert(mesh.material_ids.end(), mesh.triangles.size() - before,
                                     material);
        }
    }
    if (face_number != scan.face_count) {
        // The usemtl switches are counted in the scan's faces: the two must agree.
        throw Error(path.string() + ": internal error: tinyobjloader read " +
                    std::to_string(face_number) + " faces, the scan " +
                    std::to_string(scan.face_count));
    }
    if (skipped > 0) {
        warnings.push_back(std::to_string(skipped) +
                           " polygon(s) of zero area triangulate to nothing and were skipped");
    }
    if (not_simple > 0) {
        warnings.push_back(std::to_string(not_simple) +
                           " polygon(s) overlapping themselves (first: face " +
                           std::to_string(not_simple_face) +
                           ") have no triangulation of the same area and were skipped");
    }

    mesh.materials = std::move(materials);
    if (uses_default) {
        MeshMaterial fallback;
        fallback.name = "default";
        mesh.materials.push_back(fallback);
    }

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

    report(path, warnings, options);
    if (options.warnings != nullptr) {
        for (std::string& w : mtl_warnings)
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
