#include "embree_scene.h"

#include <librt/core/error.h>

#ifdef LIBRT_HAVE_EMBREE
#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <string>
#include <vector>
#endif

namespace librt::bench {

#ifndef LIBRT_HAVE_EMBREE

bool embree_available() { return false; }

struct EmbreeScene::Impl {};
EmbreeScene::EmbreeScene(const TriangleMesh&, EmbreeQuality) {
    throw Error("librt_bench was built without Embree");
}
EmbreeScene::~EmbreeScene() = default;
PrimitiveHit EmbreeScene::intersect(const Ray&) const { return {}; }
bool EmbreeScene::occluded(const Ray&) const { return false; }
std::size_t EmbreeScene::intersect_stream(std::span<const Ray>, std::span<PrimitiveHit>,
                                          bool) const {
    return 0;
}
std::size_t EmbreeScene::occluded_stream(std::span<const Ray>, std::span<std::uint8_t>,
                                         bool) const {
    return 0;
}
std::size_t EmbreeScene::memory_bytes() const { return 0; }
double EmbreeScene::build_seconds() const { return 0.0; }

struct EmbreeInstancedScene::Impl {};
EmbreeInstancedScene::EmbreeInstancedScene(std::span<const TriangleMesh* const>,
                                           std::span<const EmbreeInstance>, EmbreeQuality) {
    throw Error("built without Embree");
}
EmbreeInstancedScene::~EmbreeInstancedScene() = default;
PrimitiveHit EmbreeInstancedScene::intersect(const Ray&) const { return {}; }
bool EmbreeInstancedScene::occluded(const Ray&) const { return false; }
std::size_t EmbreeInstancedScene::memory_bytes() const { return 0; }
std::size_t EmbreeInstancedScene::shared_array_bytes() const { return 0; }
double EmbreeInstancedScene::build_seconds() const { return 0.0; }

#else

bool embree_available() { return true; }

namespace {

/// Bytes currently allocated by the device, kept by its memory monitor.
std::atomic<long long> g_device_bytes{0};

bool monitor(void*, ssize_t bytes, bool) {
    g_device_bytes += static_cast<long long>(bytes);
    return true;  // never veto an allocation
}

/// Embree calls this from C code: report and stop rather than throw through it.
void on_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "Embree error %d: %s\n", static_cast<int>(code), message ? message : "");
    std::abort();
}

/// The one device every scene uses (Embree picks its best ISA and all hardware threads).
/// LIBRT_EMBREE_CONFIG, when set, is its configuration string: "verbose=2" prints each
/// tree's statistics (SAH, nodes, leaf fill, bytes per triangle) after its build.
RTCDevice device() {
    static RTCDevice dev = [] {
        RTCDevice d = rtcNewDevice(std::getenv("LIBRT_EMBREE_CONFIG"));
        if (!d) throw Error("rtcNewDevice failed");
        rtcSetDeviceErrorFunction(d, on_error, nullptr);
        rtcSetDeviceMemoryMonitorFunction(d, monitor, nullptr);
        return d;
    }();
    return dev;
}

/// Serialises builds so one scene's allocations are not counted for another.
std::mutex g_build_mutex;

/// A mesh's positions and triangles in the layout Embree reads, shared with its geometry.
struct SharedArrays {
    std::vector<float> vertices;  // xyz per vertex plus 4 bytes of padding Embree may read
    std::vector<unsigned> indices;

    explicit SharedArrays(const TriangleMesh& mesh) {
        vertices.reserve(3 * mesh.positions.size() + 1);
        for (const glm::vec3& p : mesh.positions) vertices.insert(vertices.end(), {p.x, p.y, p.z});
        vertices.push_back(0.0f);
        indices.reserve(3 * mesh.triangles.size());
        for (const glm::uvec3& t : mesh.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});
    }
    [[nodiscard]] std::size_t bytes() const {
        return vertices.size() * sizeof(float) + indices.size() * sizeof(unsigned);
    }
};

RTCBuildQuality rtc_quality(EmbreeQuality quality) {
    return quality == EmbreeQuality::High ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
}

/// A committed scene of one triangle geometry over `arrays` (which must outlive it).
RTCScene triangle_scene(RTCDevice dev, const SharedArrays& arrays, EmbreeQuality quality) {
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(scene, rtc_quality(quality));
    if (quality == EmbreeQuality::Robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               arrays.vertices.data(), 0, 3 * sizeof(float),
                               arrays.vertices.size() / 3);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               arrays.indices.data(), 0, 3 * sizeof(unsigned),
                               arrays.indices.size() / 3);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
}

/// librt's ray as Embree's.
void fill_ray(RTCRay& r, const Ray& ray) {
    r.org_x = ray.origin.x;
    r.org_y = ray.origin.y;
    r.org_z = ray.origin.z;
    r.tnear = ray.t_min;
    r.dir_x = ray.direction.x;
    r.dir_y = ray.direction.y;
    r.dir_z = ray.direction.z;
    r.time = 0.0f;
    r.tfar = ray.t_max;
    r.mask = std::numeric_limits<unsigned>::max();
    r.id = 0;
    r.flags = 0;
}

/// librt's ray as Embree's closest-hit record, no hit yet.
void fill_ray_hit(RTCRayHit& rh, const Ray& ray) {
    fill_ray(rh.ray, ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// Embree's closest-hit answer as librt's.
PrimitiveHit primitive_hit(const RTCRayHit& rh) {
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
    return {rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID};
}

PrimitiveHit intersect_scene(RTCScene scene, const Ray& ray) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    fill_ray_hit(rh, ray);
    rtcIntersect1(scene, &context, &rh);
    return primitive_hit(rh);
}

bool occluded_scene(RTCScene scene, const Ray& ray) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    fill_ray(r, ray);
    rtcOccluded1(scene, &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

/// A stream's records, kept per thread so that a call allocates only when its stream is the
/// longest yet.
thread_local std::vector<RTCRayHit> t_ray_hits;
thread_local std::vector<RTCRay> t_rays;

RTCIntersectContext stream_context(bool coherent) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags =
        coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return context;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The device's bytes still held since `before`.
std::size_t bytes_since(long long before) {
    const long long after = g_device_bytes.load();
    return after > before ? static_cast<std::size_t>(after - before) : 0;
}

}  // namespace

struct EmbreeScene::Impl {
    SharedArrays arrays;
    RTCScene scene = nullptr;
    std::size_t bytes = 0;
    double seconds = 0.0;
};

EmbreeScene::EmbreeScene(const TriangleMesh& mesh, EmbreeQuality quality)
    : impl_(std::make_unique<Impl>(Impl{SharedArrays(mesh)})) {
    RTCDevice dev = device();
    const std::lock_guard lock(g_build_mutex);
    const long long before = g_device_bytes.load();
    const auto start = std::chrono::steady_clock::now();
    impl_->scene = triangle_scene(dev, impl_->arrays, quality);
    impl_->seconds = seconds_since(start);
    impl_->bytes = bytes_since(before);
}

EmbreeScene::~EmbreeScene() {
    if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
}

PrimitiveHit EmbreeScene::intersect(const Ray& ray) const {
    return intersect_scene(impl_->scene, ray);
}

bool EmbreeScene::occluded(const Ray& ray) const { return occluded_scene(impl_->scene, ray); }

std::size_t EmbreeScene::intersect_stream(std::span<const Ray> rays, std::span<PrimitiveHit> hits,
                                          bool coherent) const {
    if (hits.size() != rays.size()) throw Error("EmbreeScene::intersect_stream: sizes differ");
    if (t_ray_hits.size() < rays.size()) t_ray_hits.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) fill_ray_hit(t_ray_hits[i], rays[i]);
    RTCIntersectContext context = stream_context(coherent);
    rtcIntersect1M(impl_->scene, &context, t_ray_hits.data(), static_cast<unsigned>(rays.size()),
                   sizeof(RTCRayHit));
    std::size_t count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits[i] = primitive_hit(t_ray_hits[i]);
        count += hits[i].valid();
    }
    return count;
}

std::size_t EmbreeScene::occluded_stream(std::span<const Ray> rays, std::span<std::uint8_t> blocked,
                                         bool coherent) const {
    if (blocked.size() != rays.size()) throw Error("EmbreeScene::occluded_stream: sizes differ");
    if (t_rays.size() < rays.size()) t_rays.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) fill_ray(t_rays[i], rays[i]);
    RTCIntersectContext context = stream_context(coherent);
    rtcOccluded1M(impl_->scene, &context, t_rays.data(), static_cast<unsigned>(rays.size()),
                  sizeof(RTCRay));
    std::size_t count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        blocked[i] = t_rays[i].tfar < 0.0f ? 1 : 0;  // Embree sets tfar to -inf on a hit
        count += blocked[i];
    }
    return count;
}

std::size_t EmbreeScene::memory_bytes() const { return impl_->bytes; }

double EmbreeScene::build_seconds() const { return impl_->seconds; }

struct EmbreeInstancedScene::Impl {
    std::vector<SharedArrays> arrays;
    std::vector<RTCScene> prototypes;
    RTCScene top = nullptr;
    std::size_t bytes = 0;
    double seconds = 0.0;
};

EmbreeInstancedScene::EmbreeInstancedScene(std::span<const TriangleMesh* const> prototypes,
                                           std::span<const EmbreeInstance> instances,
                                           EmbreeQuality quality)
    : impl_(std::make_unique<Impl>()) {
    RTCDevice dev = device();
    impl_->arrays.reserve(prototypes.size());
    for (const TriangleMesh* mesh : prototypes) impl_->arrays.emplace_back(*mesh);
    const std::lock_guard lock(g_build_mutex);
    const long long before = g_device_bytes.load();
    const auto start = std::chrono::steady_clock::now();
    for (const SharedArrays& a : impl_->arrays)
        impl_->prototypes.push_back(triangle_scene(dev, a, quality));
    impl_->top = rtcNewScene(dev);
    rtcSetSceneBuildQuality(impl_->top, rtc_quality(quality));
    for (const EmbreeInstance& inst : instances) {
        if (inst.prototype >= impl_->prototypes.size())
            throw Error("EmbreeInstancedScene: instance of prototype " +
                        std::to_string(inst.prototype) + ", there are " +
                        std::to_string(impl_->prototypes.size()));
        RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, impl_->prototypes[inst.prototype]);
        // glm stores columns contiguously: Embree's column-major 4x4 layout.
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                                &inst.object_to_world[0][0]);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(impl_->top, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(impl_->top);
    impl_->seconds = seconds_since(start);
    impl_->bytes = bytes_since(before);
}

EmbreeInstancedScene::~EmbreeInstancedScene() {
    if (!impl_) return;
    if (impl_->top) rtcReleaseScene(impl_->top);
    for (RTCScene s : impl_->prototypes) rtcReleaseScene(s);
}

PrimitiveHit EmbreeInstancedScene::intersect(const Ray& ray) const {
    return intersect_scene(impl_->top, ray);
}

bool EmbreeInstancedScene::occluded(const Ray& ray) const {
    return occluded_scene(impl_->top, ray);
}

std::size_t EmbreeInstancedScene::memory_bytes() const { return impl_->bytes; }

double EmbreeInstancedScene::build_seconds() const { return impl_->seconds; }

std::size_t EmbreeInstancedScene::shared_array_bytes() const {
    std::size_t bytes = 0;
    for (const SharedArrays& a : impl_->arrays) bytes += a.bytes();
    return bytes;
}

#endif

}  // namespace librt::bench
