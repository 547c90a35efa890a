// Bidirectional path tracing (bdpt.h): the two random walks, the four kinds of connection
// (s = 0, s = 1, t = 1, general) and the power-heuristic weight over every (s, t) that
// could have made a path, computed as pbrt 3rd ed. (section 16.3.4) does, by ratios of
// the densities of each vertex sampled forward (toward the light for the camera subpath,
// away from it for the light subpath) and in reverse.
// Over 400 lines: the walks, the connections and the weights share the private PathVertex
// and its densities, and the weight is only checkable beside the code that sets them.

#include "film/camera_importance.h"
#include "geometry/ray_copy.h"
#include "integrator/light_path_start.h"
#include "integrator/mis.h"
#include "integrator/shading_correction.h"
#include "integrator/transmittance.h"
#include "material/bsdf_dispatch.h"
#include "scene/shadow_ray.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/integrator/bdpt.h>
#include <librt/light/light.h>
#include <librt/material/bsdf.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

namespace librt {
namespace {

/// Sampler dimensions of the light subpath: its light choice (1D), origin (2D) and
/// direction (2D), whether this sample traces one (1D, kLightPathChoice), then per light
/// vertex j >= 1 kLightPerVertex dimensions from kLightVertices + (j - 1)
/// kLightPerVertex: lobe (1D), direction (2D), lens point of its connection to the
/// camera (2D), roulette (1D). Between the camera subpath's bounces (below 7 * 66)
/// and the crossing decisions (SampleDimensions::kPassThrough), so no number is drawn
/// twice in one sample.
constexpr std::uint32_t kLightBase = 1u << 15u;
constexpr std::uint32_t kLightPathChoice = kLightBase + 5;
constexpr std::uint32_t kLightVertices = kLightBase + 6;
constexpr std::uint32_t kLightPerVertex = 6;
constexpr std::uint32_t kLightVertexRoulette = 5;

enum class VertexKind : std::uint8_t { Camera, Light, Surface };

/// One vertex of a subpath. Built whole by the walks and connections (no default values:
/// the arrays of them live on the stack of every sample).
struct PathVertex {
    VertexKind kind;
    bool delta;           ///< sampled by a specular lobe: no connection can reach it
    bool delta_position;  ///< a light endpoint that is a point (point, spot light)
    glm::vec3 p;          ///< position
    glm::vec3 ng;         ///< geometric normal as the primitive faces (0: none, a point)
    float offset;         ///< how far rays leave p off its surface (Hit::offset)
    glm::vec3 ns;         ///< shading normal, on ng's side (surfaces)
    glm::vec3 beta;       ///< throughput of the subpath up to this vertex, divided by its density
    float pdf_fwd;        ///< area density of this vertex as its own subpath sampled it
    float pdf_rev;        ///< area density of it sampled from the next vertex, in reverse
    std::uint32_t light;  ///< Light: the light; Surface: the light whose surface it is on
    const Material* material;  ///< Surface
    ShadingPoint sp;           ///< Surface: frame facing the direction it was reached from
    glm::vec3 wo;              ///< Surface: unit direction back along the walk (world)
};

/// An endpoint vertex (on the lens, or on a light: `light`), its pdf_rev and material empty.
PathVertex endpoint(VertexKind kind, const glm::vec3& p, const glm::vec3& n, const glm::vec3& beta,
                    float pdf_fwd, std::uint32_t light, bool delta_position) {
    PathVertex v{};
    v.kind = kind;
    v.delta = false;
    v.delta_position = delta_position;
    v.p = p;
    v.ng = n;
    v.offset = ray_offset_scale(p);
    v.ns = n;
    v.beta = beta;
    v.pdf_fwd = pdf_fwd;
    v.pdf_rev = 0.0f;
    v.light = light;
    v.material = nullptr;
    return v;
}

/// What every piece of a sample needs.
struct Context {
    const Scene& scene;
    const SceneSphere& sphere;
    const Camera* camera;  ///< for the t = 1 strategies (nullptr: none)
    SplatFilm* film;
    float margin;        ///< SplatFilm::margin()
    bool light_tracing;  ///< t = 1 strategies are used (and weighed)
    int max_depth;
    float light_paths;   ///< BidirectionalSettings::light_path_fraction
    int roulette_depth;  ///< first rouletted bounce (INT_MAX: no roulette)
};

/// The two subpaths of one sample, and what every strategy joining them shares.
struct Subpaths {
    /// The camera subpath: z0 on the lens, then the camera walk's surface vertices.
    PathVertex* camera_path;
    int camera_length;  ///< vertices in camera_path (>= 1)
    /// The light subpath: y0 on a light, then the light walk's vertices; slot 0 holds a
    /// value even without one (s = 1's weight swaps its own y0 in and back).
    PathVertex* light_path;
    int light_length;      ///< vertices in light_path (0: none traced in this sample)
    float light_nee;       ///< nee_area_pdf(y0, y1): mis_weight's s' = 1 term for every s >= 2
    float per_light_path;  ///< 1 / light_path_fraction, the factor of s >= 2 and t = 1
};

/// The shadow segment between vertices a and b (either may have a zero normal, a point):
/// the fraction of light it lets through (transmittance, or 1 / 0 without Null lobes).
glm::vec3 segment(const Scene& scene, const PathVertex& a, const PathVertex& b) {
    return shadow_transmittance(scene, spawn_ray_between(a.p, a.ng, a.offset, b.p, b.ng, b.offset));
}

/// The shadow segment from vertex a to a point on no surface (the lens).
glm::vec3 segment(const Scene& scene, const PathVertex& a, const glm::vec3& lens) {
    return lens_transmittance(scene,
                              spawn_ray_between(a.p, a.ng, a.offset, lens, glm::vec3(0.0f), 0.0f));
}

/// The density of direction `to` at a surface vertex reached from direction `from` (both
/// unit, world, away from the surface), as sample() draws it; the frame faces `from`.
float bsdf_pdf(const PathVertex& v, const glm::vec3& from, const glm::vec3& to) {
    // The vertex's own frame when `from` is on the side it was reached from: at() would
    // build the same bits (most calls; 16 % fewer instructions here, callgrind).
    if ((glm::dot(-from, v.ng) < 0.0f) == v.sp.frame.front) {
        return bsdfs::pdf_bsdf(*v.material, v.sp, v.sp.frame.to_local(from),
                               v.sp.frame.to_local(to));
    }
    const ShadingFrame frame = ShadingFrame::at(v.ns, v.ng, -from);
    const ShadingPoint sp{frame, v.sp.albedo};
    return bsdfs::pdf_bsdf(*v.material, sp, frame.to_local(from), frame.to_local(to));
}

/// f at a surface vertex toward world direction `to`, for light arriving along the walk's
/// other end (wo): f(wo, to). librt's BSDFs are symmetric, so this is also the adjoint
/// (light from wo leaving toward `to`) a light subpath needs, up to shading_correction
/// (shading_correction.h).
glm::vec3 bsdf_f(const PathVertex& v, const glm::vec3& to) {
    return bsdfs::eval_bsdf(*v.material, v.sp, v.sp.frame.to_local(v.wo), v.sp.frame.to_local(to));
}

/// A solid-angle density at `from` turned into an area density at `to` (|cos| at `to`
/// when it is on a surface; a point or a lens point has none).
float to_area(float pdf_dir, const PathVertex& from, const PathVertex& to) {
    const glm::vec3 d = to.p - from.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return 0.0f;
    float pdf = pdf_dir / d2;
    if (to.kind != VertexKind::Camera && glm::dot(to.ng, to.ng) > 0.0f)
        pdf *= std::fabs(glm::dot(to.ng, d)) / std::sqrt(d2);
    return pdf;
}

/// Density of the light vertex v (an emitter, light `v.light`) as the origin of a light
/// subpath emitting toward `toward`: light choice times sample_le's origin density.
float light_origin_pdf(const Context& c, const PathVertex& v, const PathVertex& toward) {
    if (v.light == kInvalidId) return 0.0f;
    const glm::vec3 dir = glm::normalize(toward.p - v.p);
    const LightLePdf le = pdf_le(c.scene.lights()[v.light], c.sphere, v.p, v.ng, dir);
    return c.scene.light_sampler().pmf(v.light) * le.pos;
}

/// Area density at `next` of the direction a light vertex v (an emitter) emits toward it.
float light_direction_pdf(const Context& c, const PathVertex& v, const PathVertex& next) {
    if (v.light == kInvalidId) return 0.0f;
    const glm::vec3 dir = glm::normalize(next.p - v.p);
    const LightLePdf le = pdf_le(c.scene.lights()[v.light], c.sphere, v.p, v.ng, dir);
    return to_area(le.dir, v, next);
}

/// Area density at the light endpoint x0 of next-event estimation from x1 drawing it:
/// the light choice times sample_li's solid-angle density, turned into area at x0.
float nee_area_pdf(const Context& c, const PathVertex& x0, const PathVertex& x1) {
    const glm::vec3 d = x0.p - x1.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return 0.0f;
    const glm::vec3 dir = d / std::sqrt(d2);
    const float pdf =
        c.scene.light_sampler().pmf(x0.light) * pdf_li(c.scene.lights()[x0.light], x1.p, dir);
    return to_area(pdf, x1, x0);
}

/// Area density at `next` of vertex v sampling the direction toward it, v having been
/// reached from `prev` (unused for the camera and light endpoints).
float pdf_to(const Context& c, const PathVertex& v, const PathVertex* prev,
             const PathVertex& next) {
    switch (v.kind) {
        case VertexKind::Camera: {
            if (c.camera == nullptr) return 0.0f;
            Ray r;
            r.origin = v.p;
            r.direction = next.p - v.p;
            return to_area(pdf_we(*c.camera, r, c.margin).dir, v, next);
        }
        case VertexKind::Light:
            return light_direction_pdf(c, v, next);
        case VertexKind::Surface:
            break;
    }
    if (prev == nullptr) return 0.0f;
    const glm::vec3 from = glm::normalize(prev->p - v.p);
    const glm::vec3 to = glm::normalize(next.p - v.p);
    return to_area(bsdf_pdf(v, from, to), v, next);
}

/// The power-heuristic weight of the path of light vertices light_path[0, s) and camera
/// vertices camera_path[0, t) made by strategy (s, t); `sampled` replaces light_path[0]
/// (s = 1) or camera_path[0] (t = 1), the endpoint that strategy drew itself (nullptr for
/// the others). Every other strategy's density comes from the
/// ratios of reverse to forward densities along the path (pbrt 3rd ed. eq. 16.19-16.20);
/// the densities of the connection's two ends and their neighbours are the ones that
/// change, set here and restored after. paths.light_nee is nee_area_pdf(y0, y1), which
/// every s >= 2 strategy needs and which is the same for all of them: computed once per
/// light subpath (nee_area_pdf's share of a bidirectional render's instructions fell from
/// 4.3 % to 2.9 %, callgrind on cornell_pbr.glb).
float mis_weight(const Context& c, Subpaths& paths, const PathVertex* sampled, int s, int t) {
    if (s + t == 2) return 1.0f;
    PathVertex* const light_path = paths.light_path;
    PathVertex* const camera_path = paths.camera_path;
    const PathVertex saved_end = s == 1 ? light_path[0] : camera_path[0];
    if (s == 1) light_path[0] = *sampled;
    if (t == 1) camera_path[0] = *sampled;
    PathVertex* qs = s > 0 ? &light_path[s - 1] : nullptr;
    PathVertex* pt = &camera_path[t - 1];
    PathVertex* qs_minus = s > 1 ? &light_path[s - 2] : nullptr;
    PathVertex* pt_minus = t > 1 ? &camera_path[t - 2] : nullptr;
    // Save what changes.
    const float pt_rev = pt->pdf_rev;
    const bool pt_delta = pt->delta;
    const float pt_minus_rev = pt_minus != nullptr ? pt_minus->pdf_rev : 0.0f;
    const float qs_rev = qs != nullptr ? qs->pdf_rev : 0.0f;
    const bool qs_delta = qs != nullptr && qs->delta;
    const float qs_minus_rev = qs_minus != nullptr ? qs_minus->pdf_rev : 0.0f;

    // The connected vertices are joined, not sampled: no delta there.
    pt->delta = false;
    if (qs != nullptr) qs->delta = false;
    pt->pdf_rev = s > 0 ? pdf_to(c, *qs, qs_minus, *pt)
                        : (pt_minus != nullptr ? light_origin_pdf(c, *pt, *pt_minus) : 0.0f);
    if (pt_minus != nullptr)
        pt_minus->pdf_rev =
            s > 0 ? pdf_to(c, *pt, qs, *pt_minus) : light_direction_pdf(c, *pt, *pt_minus);
    if (qs != nullptr) qs->pdf_rev = pdf_to(c, *pt, pt_minus, *qs);
    if (qs_minus != nullptr) qs_minus->pdf_rev = pdf_to(c, *qs, pt, *qs_minus);

    // The s' = 1 strategy draws the light endpoint x0 by sample_li from x1, not by
    // sample_le's origin density, which the ratios assume for every s' >= 1: its term is
    // scaled by c^2, c = (its real density of x0) / (the origin density); with s = 1 the
    // path's own density is the real one, so every other term is divided by c^2. Without
    // this a light close to x1 (a ceiling just above a panel), which sample_li draws by
    // solid angle, got the tiny weight that area sampling would deserve there.
    const PathVertex* x0 = s > 0 ? &light_path[0] : pt;
    const PathVertex* x1 = s > 1 ? &light_path[1] : (s == 1 ? pt : pt_minus);
    const float origin = s > 0 ? light_path[0].pdf_fwd : pt->pdf_rev;
    double c2 = 1.0;
    if (x1 != nullptr && x0->light != kInvalidId && !x0->delta_position && origin > 0.0f) {
        const float nee = s >= 2 ? paths.light_nee : nee_area_pdf(c, *x0, *x1);
        const double ratio = double(nee) / double(origin);
        if (ratio > 0.0 && std::isfinite(ratio)) c2 = ratio * ratio;
    }
    // Sample counts: a strategy that needs the light subpath (s' >= 2 or t' = 1) is taken
    // in a fraction light_paths of the samples, the others in every sample; each term is
    // (n' p' / n p)^2, so it is scaled by the square of its count over this strategy's.
    const double fraction = c.light_paths;
    const bool needs_light_path = s >= 2 || t == 1;
    const double to_light_path = needs_light_path ? 1.0 : fraction * fraction;
    const double to_camera_only = needs_light_path ? 1.0 / (fraction * fraction) : 1.0;
    // A zero density is a delta's (handled by the flags): remapped to 1 in the ratios.
    const auto remap = [](float f) { return f != 0.0f ? f : 1.0f; };
    double sum = 0.0;
    double r = 1.0;
    for (int i = t - 1; i > 0; --i) {
        r *= double(remap(camera_path[i].pdf_rev)) / double(remap(camera_path[i].pdf_fwd));
        // i = 1 is the strategy that joins a light subpath to the lens (t = 1); with s = 0,
        // i = t - 1 is next-event estimation (s' = 1); every other i has s' = s + t - i >= 2.
        const bool next_event = s == 0 && i == t - 1;
        if (!camera_path[i].delta && !camera_path[i - 1].delta && (i > 1 || c.light_tracing))
            sum += r * r * (next_event ? c2 * to_camera_only : to_light_path);
    }
    r = 1.0;
    for (int i = s - 1; i >= 0; --i) {
        r *= double(remap(light_path[i].pdf_rev)) / double(remap(light_path[i].pdf_fwd));
        const bool delta_light = i > 0 ? light_path[i - 1].delta : light_path[0].delta_position;
        // s' = i: 0 and 1 need no light subpath.
        if (!light_path[i].delta && !delta_light)
            sum += r * r * (i == 1 ? c2 : 1.0) * (i >= 2 ? to_light_path : to_camera_only);
    }
    if (s == 1) sum /= c2;

    pt->pdf_rev = pt_rev;
    pt->delta = pt_delta;
    if (pt_minus != nullptr) pt_minus->pdf_rev = pt_minus_rev;
    if (qs != nullptr) {
        qs->pdf_rev = qs_rev;
        qs->delta = qs_delta;
    }
    if (qs_minus != nullptr) qs_minus->pdf_rev = qs_minus_rev;
    if (s == 1) light_path[0] = saved_end;
    if (t == 1) camera_path[0] = saved_end;
    const double w = 1.0 / (1.0 + sum);
    return std::isfinite(w) ? float(w) : 0.0f;
}

enum class Transport : std::uint8_t { Radiance, Importance };

/// Where the camera walk's last ray left the scene (lights at infinity see it).
struct Escape {
    bool escaped = false;
    glm::vec3 direction{0.0f};
    glm::vec3 beta{0.0f};
    int from = 0;          ///< index of the vertex it left
    float pdf_dir = 0.0f;  ///< its solid-angle density there (0: specular or the camera)
};

/// Extends path[0, 1) (the endpoint, set by the caller) by a random walk from `ray` with
/// throughput `beta` (its direction drawn at path[0] with solid-angle density pdf_dir; 0
/// for a delta), up to max_vertices vertices; returns the count. The camera walk draws
/// each bounce's numbers from SampleDimensions::bounce(i), the light walk from
/// kLightVertices. Surfaces with a Null lobe are crossed as PathTracer crosses them. With
/// `widened` (the light walk), a first vertex after a delta light scatters with its lobe
/// widened there (bsdfs::delta_light_material), as PathTracer's light sample sees it.
int random_walk(const Context& c, Ray ray, glm::vec3 beta, float pdf_dir, Transport mode,
                Sampler& sampler, PathVertex* path, ShadedMaterial* scratch, int max_vertices,
                std::uint32_t& decisions, Escape* escape, Material* widened = nullptr) {
    int n = 1;
    int hidden_skips = 0;
    // Roulette survives with the throughput relative to the walk's start (a light
    // subpath's carries the light's radiance and densities).
    const float start = max_component(beta);
    while (n < max_vertices) {
        Hit hit;
        if (!c.scene.intersect_for_shading(ray, hit)) {
            if (escape != nullptr) *escape = {true, ray.direction, beta, n - 1, pdf_dir};
            break;
        }
        // Camera rays pass objects hidden from the camera and culled backs, as PathTracer's do.
        if (mode == Transport::Radiance && n == 1 && c.scene.camera_may_pass() &&
            c.scene.camera_passes(hit, ray.direction)) {
            if (++hidden_skips > 64) break;
            detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, ray.direction);
            continue;
        }
        const Material& shaded = c.scene.shade(hit, ray.direction, scratch[n]);
        // Regularised next to a delta light, in sampling and densities too: every strategy
        // that makes a path then sees the same integrand (docs/materials-and-lights.md).
        const Material& m = widened != nullptr && n == 1 && path[0].delta_position &&
                                    bsdfs::delta_light_material(shaded, *widened)
                                ? *widened
                                : shaded;
        const BsdfLobe lobes = bsdfs::lobes_of(m);
        const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : c.scene.albedo(hit);
        if (has(lobes, BsdfLobe::Null)) {
            // Crossed as PathTracer crosses it (cross_null).
            const Crossing x = cross_null(c.scene, m, hit, ray.direction, sampler, decisions++);
            beta *= x.weight;
            if (x.crossed) {
                if (decisions > kMaxCrossingDecisions) break;
                detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, ray.direction);
                continue;
            }
        }
        PathVertex& v = path[n];
        PathVertex& prev = path[n - 1];
        v.kind = VertexKind::Surface;
        v.delta = false;
        v.delta_position = false;
        v.p = hit.point;
        v.ng = hit.geometric_normal;
        v.offset = hit.offset;
        v.ns = hit.shading_normal;
        v.beta = beta;
        v.pdf_fwd = to_area(pdf_dir, prev, v);
        v.pdf_rev = 0.0f;
        v.light = m.emits() ? c.scene.light_of_hit(hit) : kInvalidId;
        v.material = &m;
        v.sp = ShadingPoint{
            ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction), albedo};
        v.wo = -ray.direction;
        ++n;
        if (n >= max_vertices || lobes == BsdfLobe::None) break;

        // The next direction, from this vertex's own dimensions.
        const auto j = static_cast<std::uint32_t>(n - 2);  // 0 for the first surface vertex
        const std::uint32_t dim = mode == Transport::Radiance
                                      ? SampleDimensions::bounce(j)
                                      : kLightVertices + j * kLightPerVertex;
        sampler.set_dimension(mode == Transport::Radiance ? dim + SampleDimensions::kBounceLobe
                                                          : dim);
        const float uc = sampler.next_1d();
        sampler.set_dimension(mode == Transport::Radiance ? dim + SampleDimensions::kBounceBsdf
                                                          : dim + 1);
        const glm::vec2 u = sampler.next_2d();
        const glm::vec3 wo_local = v.sp.frame.to_local(v.wo);
        const BsdfSample bs = bsdfs::sample_bsdf(m, v.sp, wo_local, uc, u);
        if (!bs.valid()) break;
        const glm::vec3 wi = v.sp.frame.to_world(bs.wi);
        beta *= bs.weight;
        if (mode == Transport::Importance) beta *= shading_correction(v.ns, v.ng, v.wo, wi);
        float pdf_rev = 0.0f;
        if (has(bs.lobe, BsdfLobe::Specular)) {
            v.delta = true;
            pdf_dir = 0.0f;
        } else {
            pdf_dir = bs.pdf;
            pdf_rev = bsdf_pdf(v, wi, v.wo);
        }
        prev.pdf_rev = to_area(pdf_rev, v, prev);
        if (!(max_component(beta) > 0.0f)) break;
        if (static_cast<int>(j) >= c.roulette_depth) {
            // Survive with probability q, reweighted by 1/q (PathTracer's rule).
            const float q = std::min(0.95f, max_component(beta) / start);
            sampler.set_dimension(mode == Transport::Radiance
                                      ? dim + SampleDimensions::kBounceRoulette
                                      : dim + kLightVertexRoulette);
            if (!(q > 0.0f) || sampler.next_1d() >= q) break;
            beta /= q;
        }
        detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, wi);
    }
    return n;
}

/// The radiance a surface vertex on an emitter sends back along its walk (0 from the back
/// of a one-sided light).
glm::vec3 emitted(const Context& c, const PathVertex& v) {
    if (v.kind != VertexKind::Surface || !v.material->emits()) return glm::vec3(0.0f);
    if (v.light != kInvalidId && c.scene.lights()[v.light].one_sided &&
        !(glm::dot(v.wo, v.ng) > 0.0f))
        return glm::vec3(0.0f);
    return v.material->emission;
}

/// True when a vertex can be joined to another: a surface with a lobe that has a density.
bool connectible(const PathVertex& v) {
    return v.kind != VertexKind::Surface || has_non_specular(bsdfs::lobes_of(*v.material));
}

/// Lights at infinity: what the camera walk's last ray met, against next-event estimation
/// at the vertex it left (s = 0 and s = 1 only: PathTracer's weights, as lights at infinity
/// start no light subpath).
glm::vec3 escaped_light(const Context& c, const Escape& escape, const Subpaths& paths) {
    glm::vec3 sum(0.0f);
    for (const std::uint32_t i : c.scene.infinite_lights()) {
        const Light& light = c.scene.lights()[i];
        if (escape.from == 0 && !light.camera_visible) continue;
        const glm::vec3 le = escaped_radiance(light, escape.direction);
        if (!(max_component(le) > 0.0f)) continue;
        float w = 1.0f;
        if (escape.from > 0 && escape.pdf_dir > 0.0f) {
            const float pl = c.scene.light_sampler().pmf(i) *
                             pdf_li(light, paths.camera_path[escape.from].p, escape.direction);
            w = power_heuristic(escape.pdf_dir, pl);
        }
        sum += escape.beta * le * w;
    }
    return sum;
}

/// Strategy s = 0: camera vertex z(t-1) (t >= 2) is on an emitter the camera walk hit.
glm::vec3 camera_path_hits_light(const Context& c, Subpaths& paths, int t) {
    const PathVertex& pt = paths.camera_path[t - 1];
    const glm::vec3 le = emitted(c, pt);
    if (!(max_component(le) > 0.0f)) return glm::vec3(0.0f);
    // An emitter no light samples (an emissive mesh): only this strategy finds it.
    const float w = pt.light == kInvalidId ? 1.0f : mis_weight(c, paths, nullptr, 0, t);
    return pt.beta * le * w;
}

/// Strategy s = 1: next-event estimation from camera vertex z(t-1) (t >= 2), its light and
/// point drawn by sample_li from that bounce's light dimensions, as PathTracer draws them
/// (it needs no light subpath).
glm::vec3 connect_to_light(const Context& c, Subpaths& paths, int t, Sampler& sampler) {
    const Scene& scene = c.scene;
    const LightSampler& lights = scene.light_sampler();
    const PathVertex& pt = paths.camera_path[t - 1];
    if (!connectible(pt)) return glm::vec3(0.0f);
    const std::uint32_t dim = SampleDimensions::bounce(static_cast<std::uint32_t>(t - 2));
    sampler.set_dimension(dim + SampleDimensions::kBounceLightChoice);
    const float u_light = lights.size() > 1 ? sampler.next_1d() : 0.0f;
    sampler.set_dimension(dim + SampleDimensions::kBounceLight);
    const glm::vec2 u = sampler.next_2d();
    const SampledLight chosen = lights.sample(u_light);
    if (!chosen.valid()) return glm::vec3(0.0f);
    const Light& light = scene.lights()[chosen.light];
    const LightLiSample ls = sample_li(light, pt.p, u);
    if (!ls.valid()) return glm::vec3(0.0f);
    // Next to a delta light the vertex scatters with its lobe widened (PathTracer's rule,
    // and the light walk's at y1): for f and for the weight's densities, restored after.
    std::optional<Material> widened;  // constructed for delta lights only
    struct Restore {
        PathVertex& v;
        const Material* own;
        ~Restore() { v.material = own; }
    } restore{paths.camera_path[t - 1], pt.material};
    if (ls.is_delta && bsdfs::delta_light_material(*pt.material, widened.emplace()))
        paths.camera_path[t - 1].material = &*widened;
    const glm::vec3 f = bsdf_f(pt, ls.wi) * std::fabs(glm::dot(pt.ns, ls.wi));
    glm::vec3 contrib = pt.beta * f * ls.radiance / (chosen.pmf * ls.pdf);
    if (!(max_component(contrib) > 0.0f)) return glm::vec3(0.0f);
    contrib *= shadow_transmittance(
        scene, spawn_ray_to(pt.p, pt.ng, pt.offset, ls.wi, ls.distance, ls.end_slope),
        light.object);
    if (!(max_component(contrib) > 0.0f)) return glm::vec3(0.0f);
    float w;
    if (is_infinite(light)) {
        // PathTracer's two strategies (lights at infinity start no subpath).
        w = ls.is_delta ? 1.0f : power_heuristic(chosen.pmf * ls.pdf, bsdf_pdf(pt, pt.wo, ls.wi));
    } else {
        // The light endpoint y0 this strategy drew, as the weight sees it.
        const glm::vec3 q = pt.p + ls.wi * ls.distance;
        const glm::vec3 nq = surface_normal(light, q);
        const LightLePdf le = pdf_le(light, c.sphere, q, nq, -ls.wi);
        const PathVertex sampled = endpoint(VertexKind::Light, q, nq, glm::vec3(0.0f),
                                            chosen.pmf * le.pos, chosen.light, ls.is_delta);
        w = mis_weight(c, paths, &sampled, 1, t);
    }
    return contrib * w;
}

/// Strategy t = 1: light vertex y(s-1) (s >= 2) joined to a point on the lens drawn from
/// that light vertex's lens dimensions, splatted where it lands on the film.
void splat_to_camera(const Context& c, Subpaths& paths, int s, Sampler& sampler) {
    const PathVertex& qs = paths.light_path[s - 1];
    if (!connectible(qs)) return;
    const auto j = static_cast<std::uint32_t>(s - 2);
    sampler.set_dimension(kLightVertices + j * kLightPerVertex + 3);
    const glm::vec2 u_lens = sampler.next_2d();
    const CameraWi cw = sample_wi(*c.camera, qs.p, u_lens, c.margin);
    if (!cw.valid) return;
    const glm::vec3 f = bsdf_f(qs, cw.wi) * shading_correction(qs.ns, qs.ng, qs.wo, cw.wi);
    glm::vec3 contrib = qs.beta * f * (std::fabs(glm::dot(qs.ns, cw.wi)) * cw.weight);
    if (!(max_component(contrib) > 0.0f)) return;
    contrib *= segment(c.scene, qs, cw.view_start);
    if (!(max_component(contrib) > 0.0f)) return;
    // The camera endpoint z0 this strategy drew, as the weight sees it.
    const PathVertex sampled = endpoint(VertexKind::Camera, cw.lens_point, glm::vec3(0.0f),
                                        glm::vec3(0.0f), cw.pdf_pos, kInvalidId, false);
    const float w = mis_weight(c, paths, &sampled, s, 1);
    c.film->add(cw.raster, contrib * (w * paths.per_light_path));
}

/// Strategy s >= 2, t >= 2: the ends y(s-1) and z(t-1) of both subpaths joined by a shadow
/// segment.
glm::vec3 connect_subpaths(const Context& c, Subpaths& paths, int s, int t) {
    const PathVertex& qs = paths.light_path[s - 1];
    const PathVertex& pt = paths.camera_path[t - 1];
    if (!connectible(qs) || !connectible(pt)) return glm::vec3(0.0f);
    glm::vec3 d = pt.p - qs.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return glm::vec3(0.0f);
    d /= std::sqrt(d2);
    const glm::vec3 fq = bsdf_f(qs, d) * shading_correction(qs.ns, qs.ng, qs.wo, d);
    const glm::vec3 fp = bsdf_f(pt, -d);
    const float g = std::fabs(glm::dot(qs.ns, d)) * std::fabs(glm::dot(pt.ns, d)) / d2;
    glm::vec3 contrib = qs.beta * fq * fp * pt.beta * g;
    if (!(max_component(contrib) > 0.0f)) return glm::vec3(0.0f);
    contrib *= segment(c.scene, qs, pt);
    if (!(max_component(contrib) > 0.0f)) return glm::vec3(0.0f);
    return contrib * (mis_weight(c, paths, nullptr, s, t) * paths.per_light_path);
}

/// The light subpath of one sample, into light_path; returns its length (0: none). Traced
/// in a fraction c.light_paths of the samples (chosen by the sample's own number), from a
/// light of finite extent chosen by power (start_light_path), its walk up to max_depth + 1
/// vertices.
int trace_light_path(const Context& c, Sampler& sampler, PathVertex* light_path,
                     ShadedMaterial* scratch, std::uint32_t& decisions, Material* widened) {
    if (c.light_paths < 1.0f) {
        sampler.set_dimension(kLightPathChoice);
        if (!(sampler.next_1d() < c.light_paths)) return 0;
    }
    if (!c.scene.light_sampler().any() || c.max_depth < 1) return 0;
    const LightPathStart start = start_light_path(c.scene, c.sphere, sampler, kLightBase);
    if (!start.valid) return 0;
    const LightLeSample& le = start.le;
    const float pdf0 = start.chosen.pmf * le.pdf_pos;
    light_path[0] = endpoint(VertexKind::Light, le.origin, le.normal, le.radiance / pdf0, pdf0,
                             start.chosen.light, le.delta_position);
    light_path[0].offset = start.offset();
    const glm::vec3 beta = light_path[0].beta * (start.cosine() / le.pdf_dir);
    return random_walk(c, start.ray(), beta, le.pdf_dir, Transport::Importance, sampler, light_path,
                       scratch, c.max_depth + 1, decisions, nullptr, widened);
}

}  // namespace

BidirectionalPathTracer::BidirectionalPathTracer(const BidirectionalSettings& settings)
    : settings_(settings) {
    if (settings.max_depth < 0 || settings.max_depth > BidirectionalSettings::kMaxDepth)
        throw Error("max_depth = " + std::to_string(settings.max_depth) + ": must be in [0, " +
                    std::to_string(BidirectionalSettings::kMaxDepth) + "]");
    if (!(settings.light_path_fraction > 0.0f && settings.light_path_fraction <= 1.0f))
        throw Error("light_path_fraction = " + std::to_string(settings.light_path_fraction) +
                    ": must be in (0, 1]");
    if (settings.russian_roulette_depth < 0)
        throw Error("russian_roulette_depth = " + std::to_string(settings.russian_roulette_depth) +
                    ": must be >= 0");
}

void BidirectionalPathTracer::preprocess(const Scene& scene) { sphere_ = scene.bounding_sphere(); }

glm::vec3 BidirectionalPathTracer::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    return li_splatting(scene, ray, sampler, SplatTarget{});
}

glm::vec3 BidirectionalPathTracer::li_splatting(const Scene& scene, const Ray& camera_ray,
                                                Sampler& sampler, const SplatTarget& target) const {
    // The t = 1 strategies only where a join to the lens passes what camera rays pass:
    // not through objects hidden from the camera (without them every weight leaves t = 1
    // out, and the image stays unbiased). A near clip plane's skipped space the join
    // leaves out itself (CameraWi::view_start).
    const bool tracing = settings_.light_tracing && target.camera != nullptr &&
                         target.film != nullptr &&
                         target.camera->settings().projection == Projection::Perspective &&
                         !scene.may_hide_objects();
    const Context c{scene,
                    sphere_,
                    tracing ? target.camera : nullptr,
                    tracing ? target.film : nullptr,
                    tracing ? target.film->margin() : 0.0f,
                    tracing,
                    settings_.max_depth,
                    settings_.light_path_fraction,
                    settings_.russian_roulette ? settings_.russian_roulette_depth
                                               : std::numeric_limits<int>::max()};
    constexpr int kMax = BidirectionalSettings::kMaxDepth;
    PathVertex camera_path[kMax + 2];
    PathVertex light_path[kMax + 1];
    ShadedMaterial camera_scratch[kMax + 2];
    ShadedMaterial light_scratch[kMax + 1];
    std::uint32_t decisions = 0;

    Ray ray = camera_ray;
    const float len = glm::length(ray.direction);
    if (!(len > 0.0f) || !std::isfinite(len)) return glm::vec3(0.0f);
    ray.direction /= len;
    ray.t_min *= len;
    ray.t_max *= len;

    // The camera subpath: z0 on the lens, then up to max_depth + 1 surface vertices.
    camera_path[0] = endpoint(VertexKind::Camera, ray.origin, glm::vec3(0.0f), glm::vec3(1.0f),
                              1.0f, kInvalidId, false);
    // The density of the camera ray's direction (what the t = 1 strategy's ratio needs).
    const float camera_pdf = tracing ? pdf_we(*c.camera, ray, c.margin).dir : 1.0f;
    Escape escape;
    const int camera_length =
        random_walk(c, ray, glm::vec3(1.0f), camera_pdf, Transport::Radiance, sampler, camera_path,
                    camera_scratch, settings_.max_depth + 2, decisions, &escape);
    Material widened_y1;  // y1's material when a delta light widens its lobe
    const int light_length =
        trace_light_path(c, sampler, light_path, light_scratch, decisions, &widened_y1);
    Subpaths paths{
        camera_path, camera_length, light_path, light_length,
        // What mis_weight's s' = 1 correction needs for every s >= 2 (see there).
        light_length >= 2 && light_path[0].light != kInvalidId && !light_path[0].delta_position
            ? nee_area_pdf(c, light_path[0], light_path[1])
            : 0.0f,
        1.0f / settings_.light_path_fraction};
    // Without a light subpath, s = 1's weight still swaps its vertex into light_path[0] and
    // back: give that slot a value.
    if (light_length == 0) light_path[0] = PathVertex{};

    glm::vec3 radiance(0.0f);
    if (escape.escaped && escape.from <= settings_.max_depth)
        radiance += escaped_light(c, escape, paths);
    // Every (s, t) of s light and t camera vertices within the depth limit, t outer so the
    // sum keeps one order.
    for (int t = 1; t <= camera_length; ++t) {
        // s = 1 (next-event estimation) needs no light subpath: it draws its own light.
        for (int s = 0; s <= std::max(light_length, 1); ++s) {
            const int depth = s + t - 2;
            if ((s == 1 && t == 1) || depth < 0 || depth > settings_.max_depth) continue;
            if (t == 1 && !tracing) continue;
            if (s == 0) {
                if (t >= 2) radiance += camera_path_hits_light(c, paths, t);
            } else if (s == 1) {
                radiance += connect_to_light(c, paths, t, sampler);
            } else if (t == 1) {
                splat_to_camera(c, paths, s, sampler);
            } else {
                radiance += connect_subpaths(c, paths, s, t);
            }
        }
    }
    return guard(radiance);
}

}  // namespace librt
