#include "geometry/teapot_data.h"

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/geometry/procedural.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace librt {

namespace {

void check_center_radius(const char* fn, const glm::vec3& center, float radius) {
    if (!finite(center)) {
        throw Error(std::string(fn) + ": center is not finite");
    }
    if (!(radius > 0.0f) || !std::isfinite(radius)) {
        throw Error(std::string(fn) + ": radius = " + std::to_string(radius) +
                    ": must be positive and finite");
    }
}

void check_range(const char* fn, const char* name, long long value, long long lo, long long hi) {
    if (value < lo || value > hi) {
        throw Error(std::string(fn) + ": " + name + " = " + std::to_string(value) +
                    ": must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
}

/// Refuses a mesh of more than kMaxProceduralVertices before anything is allocated.
void check_vertex_count(const char* fn, const std::string& what, std::uint64_t vertices) {
    if (vertices > kMaxProceduralVertices) {
        throw Error(std::string(fn) + ": " + what + " gives " + std::to_string(vertices) +
                    " vertices, more than the limit of " + std::to_string(kMaxProceduralVertices));
    }
}

// ---------------------------------------------------------------------------------------------
// Teapot

/// Cubic Bernstein polynomials B_i(t) = C(3,i) t^i (1-t)^(3-i) and their derivatives.
struct Bernstein {
    std::array<double, 4> b;
    std::array<double, 4> db;
};

Bernstein bernstein(double t) {
    const double s = 1.0 - t;
    return {{s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t},
            // d/dt of the above: -3s^2, 3s^2 - 6ts, 6ts - 3t^2, 3t^2.
            {-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t}};
}

using ControlGrid = std::array<glm::dvec3, 16>;  // row-major: 4 rows along u, 4 along v

/// A point of a bicubic patch with its partial derivatives.
struct PatchSample {
    glm::dvec3 p{0.0}, du{0.0}, dv{0.0};
};

/// P(u, v) = sum_ij B_i(u) B_j(v) C_ij, and its partials by differentiating B_i or B_j.
PatchSample evaluate(const ControlGrid& c, const Bernstein& bu, const Bernstein& bv) {
    PatchSample s;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            const glm::dvec3& cp = c[static_cast<std::size_t>(4 * i + j)];
            s.p += bu.b[i] * bv.b[j] * cp;
            s.du += bu.db[i] * bv.b[j] * cp;
            s.dv += bu.b[i] * bv.db[j] * cp;
        }
    }
    return s;
}

/// Outward normal: dP/dv x dP/du (the published patches run clockwise seen from outside).
glm::dvec3 patch_normal(const PatchSample& s) { return glm::cross(s.dv, s.du); }

// The data's surface extremes (z up), found by dense sampling: the handle reaches x = -3,
// the spout's lip x = 3.434075; the body y = +-2; the bottom z = 0, the knob z = 3.15.
constexpr double kDataXMin = -3.0, kDataXMax = 3.434075;
constexpr double kDataZMin = 0.0, kDataZMax = 3.15;
constexpr double kTeapotScale = 2.0 / (kDataXMax - kDataXMin);
constexpr glm::dvec3 kDataCenter{0.5 * (kDataXMin + kDataXMax), 0.0, 0.5 * (kDataZMin + kDataZMax)};

/// Data (z up) to librt's frame: centred, x spanning [-1, 1], and rotated -90 degrees about
/// x, (x, y, z) -> (x, z, -y), so z becomes up without mirroring the winding.
glm::dvec3 to_librt_frame(const std::array<float, 3>& p) {
    const glm::dvec3 q = (glm::dvec3(p[0], p[1], p[2]) - kDataCenter) * kTeapotScale;
    return {q.x, q.z, -q.y};
}

}  // namespace

TriangleMesh make_uv_sphere(const glm::vec3& center, float radius, int segments, int rings) {
    check_center_radius("make_uv_sphere", center, radius);
    check_range("make_uv_sphere", "segments", segments, 3, 1 << 15);
    check_range("make_uv_sphere", "rings", rings, 2, 1 << 15);
    check_vertex_count(
        "make_uv_sphere",
        "segments = " + std::to_string(segments) + ", rings = " + std::to_string(rings),
        std::uint64_t(rings + 1) * std::uint64_t(segments + 1));
    const auto S = static_cast<std::uint32_t>(segments);
    const auto R = static_cast<std::uint32_t>(rings);
    TriangleMesh m;
    const std::size_t nv = std::size_t{R + 1} * (S + 1);
    m.positions.reserve(nv);
    m.normals.reserve(nv);
    m.uvs.reserve(nv);
    for (std::uint32_t i = 0; i <= R; ++i) {
        const double v = double(i) / R;
        const double theta = kPiDouble * v;  // polar angle from +y
        for (std::uint32_t j = 0; j <= S; ++j) {
            const double u = double(j) / S;
            const double phi = (2.0 * kPiDouble) * u - kPiDouble;  // as sphere_uv
            // Spherical to Cartesian about +y; the poles exactly on the axis.
            glm::dvec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                         std::sin(theta) * std::sin(phi));
            if (i == 0 || i == R) n = {0.0, i == 0 ? 1.0 : -1.0, 0.0};
            m.normals.emplace_back(n);
            m.positions.push_back(center + radius * glm::vec3(n));
            m.uvs.emplace_back(static_cast<float>(u), static_cast<float>(v));
        }
    }
    m.triangles.reserve(2 * std::size_t{S} * (R - 1));
    for (std::uint32_t i = 0; i < R; ++i) {
        for (std::uint32_t j = 0; j < S; ++j) {
            // a -> b is +phi, a -> c is +theta; phi x theta points outward.
            const std::uint32_t a = i * (S + 1) + j, b = a + 1, c = a + S + 1, d = c + 1;
            if (i != 0) m.triangles.emplace_back(a, b, d);      // a, b are the north pole at i = 0
            if (i != R - 1) m.triangles.emplace_back(a, d, c);  // c, d are the south pole
        }
    }
    return m;
}

TriangleMesh make_icosphere(const glm::vec3& center, float radius, int subdivisions) {
    check_center_radius("make_icosphere", center, radius);
    check_range("make_icosphere", "subdivisions", subdivisions, 0, 10);

    // The icosahedron's 12 corners are the cyclic permutations of (0, +-1, +-phi).
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;  // golden ratio
    std::vector<glm::dvec3> corners;
    for (const double a : {-1.0, 1.0}) {
        for (const double b : {-phi, phi}) {
            corners.emplace_back(0.0, a, b);
            corners.emplace_back(a, b, 0.0);
            corners.emplace_back(b, 0.0, a);
        }
    }
    // Its 20 faces are the triples of corners at mutual distance 2 (the edge length),
    // wound so that their normal points away from the centre.
    std::vector<glm::uvec3> faces;
    auto adjacent = [&](std::size_t i, std::size_t j) {
        return std::abs(glm::distance(corners[i], corners[j]) - 2.0) < 1e-9;
    };
    for (std::uint32_t i = 0; i < 12; ++i) {
        for (std::uint32_t j = i + 1; j < 12; ++j) {
            for (std::uint32_t k = j + 1; k < 12; ++k) {
                if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
                const glm::dvec3 n = glm::cross(corners[j] - corners[i], corners[k] - corners[i]);
                if (glm::dot(n, corners[i]) > 0.0) {
                    faces.emplace_back(i, j, k);
                } else {
                    faces.emplace_back(i, k, j);
                }
            }
        }
    }
    std::vector<glm::dvec3> unit;  // positions on the unit sphere
    for (const glm::dvec3& c : corners) unit.push_back(glm::normalize(c));

    // Each subdivision splits a triangle into four at its edge midpoints, pushed out onto the
    // sphere; the edge map makes neighbours share their midpoint.
    for (int s = 0; s < subdivisions; ++s) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
        midpoints.reserve(faces.size() * 3 / 2);
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            const auto [it, inserted] =
                midpoints.try_emplace(key, static_cast<std::uint32_t>(unit.size()));
            if (inserted) unit.push_back(glm::normalize(unit[a] + unit[b]));
            return it->second;
        };
        std::vector<glm::uvec3> finer;
        finer.reserve(faces.size() * 4);
        for (const glm::uvec3& f : faces) {
            const std::uint32_t ab = midpoint(f.x, f.y), bc = midpoint(f.y, f.z),
                                ca = midpoint(f.z, f.x);
            finer.emplace_back(f.x, ab, ca);
            finer.emplace_back(ab, f.y, bc);
            finer.emplace_back(ca, bc, f.z);
            finer.emplace_back(ab, bc, ca);
        }
        faces = std::move(finer);
    }

    TriangleMesh m;
    m.positions.reserve(unit.size());
    m.normals.reserve(unit.size());
    for (const glm::dvec3& n : unit) {
        m.normals.emplace_back(n);
        m.positions.push_back(center + radius * glm::vec3(n));
    }
    m.triangles = std::move(faces);
    return m;
}

TriangleMesh make_quad(const glm::vec3& corner, const glm::vec3& edge_u, const glm::vec3& edge_v) {
    const glm::vec3 n = glm::cross(edge_u, edge_v);
    const float len = glm::length(n);
    if (!(len > 0.0f) || !std::isfinite(len)) {
        throw Error("make_quad: edges are parallel, zero or not finite");
    }
    TriangleMesh m;
    m.positions = {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v};
    m.normals.assign(4, n / len);
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

TriangleMesh make_box(const glm::vec3& lo, const glm::vec3& hi) {
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z) || !std::isfinite(lo.x + lo.y + lo.z) ||
        !std::isfinite(hi.x + hi.y + hi.z)) {
        throw Error("make_box: lo must be finite and below hi on every axis");
    }
    const glm::vec3 d = hi - lo;
    const glm::vec3 ex(d.x, 0, 0), ey(0, d.y, 0), ez(0, 0, d.z);
    // Each face as a quad whose edge_u x edge_v points outward.
    const std::array<std::array<glm::vec3, 3>, 6> faces = {{
        {lo, ez, ey},       // -x
        {lo + ex, ey, ez},  // +x
        {lo, ex, ez},       // -y
        {lo + ey, ez, ex},  // +y
        {lo, ey, ex},       // -z
        {lo + ez, ex, ey},  // +z
    }};
    TriangleMesh m;
    for (const auto& f : faces) {
        const TriangleMesh q = make_quad(f[0], f[1], f[2]);
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), q.positions.begin(), q.positions.end());
        m.normals.insert(m.normals.end(), q.normals.begin(), q.normals.end());
        m.uvs.insert(m.uvs.end(), q.uvs.begin(), q.uvs.end());
        for (const glm::uvec3& t : q.triangles) m.triangles.push_back(t + base);
    }
    return m;
}

TriangleMesh make_teapot(int tessellation) {
    check_range("make_teapot", "tessellation", tessellation, 1, 4096);
    check_vertex_count("make_teapot", "tessellation = " + std::to_string(tessellation),
                       std::uint64_t{teapot_patch_count} * std::uint64_t(tessellation + 1) *
                           std::uint64_t(tessellation + 1));
    const auto n = static_cast<std::uint32_t>(tessellation);
    const std::uint32_t row = n + 1;  // grid points per side

    // The basis at every grid parameter, shared by all patches.
    std::vector<Bernstein> basis(row);
    for (std::uint32_t k = 0; k <= n; ++k) basis[k] = bernstein(double(k) / n);

    TriangleMesh m;
    const std::size_t nv = std::size_t{teapot_patch_count} * row * row;
    m.positions.reserve(nv);
    m.normals.reserve(nv);
    m.uvs.reserve(nv);
    m.triangles.reserve(teapot_triangle_count(tessellation));

    for (const auto& patch : teapot_data::kPatches) {
        ControlGrid c;
        for (std::size_t k = 0; k < 16; ++k) {
            c[k] = to_librt_frame(teapot_data::kPoints[static_cast<std::size_t>(patch[k] - 1)]);
        }
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (std::uint32_t i = 0; i <= n; ++i) {
            for (std::uint32_t j = 0; j <= n; ++j) {
                const PatchSample s = evaluate(c, basis[i], basis[j]);
                glm::dvec3 normal = patch_normal(s);
                if (glm::dot(normal, normal) < 1e-24) {
                    // A collapsed edge: one partial is zero. Take the normal a tiny step
                    // towards the patch's centre; its limit is the surface normal here.
                    const double step = 1e-6;
                    const double u = double(i) / n, v = double(j) / n;
                    normal = patch_normal(evaluate(c, bernstein(u + step * (0.5 - u)),
                                                   bernstein(v + step * (0.5 - v))));
                }
                m.positions.emplace_back(s.p);
                m.normals.emplace_back(glm::normalize(normal));
                m.uvs.emplace_back(static_cast<float>(i) / static_cast<float>(n),
                                   static_cast<float>(j) / static_cast<float>(n));
            }
        }
        for (std::uint32_t i = 0; i < n; ++i) {
            for (std::uint32_t j = 0; j < n; ++j) {
                // a -> b is +v, a -> c is +u; the winding v x u is outward like the normals.
                const std::uint32_t a = base + i * row + j, b = a + 1, c2 = a + row, d = c2 + 1;
                m.triangles.emplace_back(a, b, d);
                m.triangles.emplace_back(a, d, c2);
            }
        }
    }
    return m;
}

int teapot_tessellation_for(std::size_t target) {
    // n = ceil(sqrt(target / 64)), then corrected for the square root's rounding.
    const double estimate = std::ceil(std::sqrt(double(target) / 64.0));
    int n = estimate > 4097.0 ? 4097 : std::max(1, static_cast<int>(estimate));
    while (n > 1 && teapot_triangle_count(n - 1) >= target) --n;
    while (n <= 4096 && teapot_triangle_count(n) < target) ++n;
    if (n > 4096) {
        throw Error("make_teapot_with_triangles: target = " + std::to_string(target) +
                    ": needs a tessellation above 4096");
    }
    return n;
}

TriangleMesh make_teapot_with_triangles(std::size_t target) {
    return make_teapot(teapot_tessellation_for(target));
}

}  // namespace librt
