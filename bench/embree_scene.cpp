#include "embree_scene.h"

#include <librt/core/error.h>

#ifdef LIBRT_HAVE_EMBREE
#include <embree3/rtcore.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <vector>
#endif

namespace librt::bench {

#ifndef LIBRT_HAVE_EMBREE

bool embree_available() { return false; }

struct EmbreeScene::Impl {};
EmbreeScene::EmbreeScene(const TriangleMesh&) {
    throw Error("librt_bench was built without Embree");
}
EmbreeScene::~EmbreeScene() = default;
PrimitiveHit EmbreeScene::intersect(const Ray&) const { return {}; }
bool EmbreeScene::occluded(const Ray&) const { return false; }
std::size_t EmbreeScene::memory_bytes() const { return 0; }

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

}  // namespace

struct EmbreeScene::Impl {
    std::vector<float> vertices;  // xyz per vertex plus 4 bytes of padding Embree may read
    std::vector<unsigned> indices;
    RTCScene scene = nullptr;
    std::size_t bytes = 0;
};

EmbreeScene::EmbreeScene(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
    RTCDevice dev = device();
    impl_->vertices.reserve(3 * mesh.positions.size() + 1);
    for (const glm::vec3& p : mesh.positions)
        impl_->vertices.insert(impl_->vertices.end(), {p.x, p.y, p.z});
    impl_->vertices.push_back(0.0f);
    impl_->indices.reserve(3 * mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles)
        impl_->indices.insert(impl_->indices.end(), {t.x, t.y, t.z});

    const std::lock_guard lock(g_build_mutex);
    const long long before = g_device_bytes.load();
    impl_->scene = rtcNewScene(dev);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               impl_->vertices.data(), 0, 3 * sizeof(float), mesh.positions.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               impl_->indices.data(), 0, 3 * sizeof(unsigned),
                               mesh.triangles.size());
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
    const long long after = g_device_bytes.load();
    impl_->bytes = after > before ? static_cast<std::size_t>(after - before) : 0;
}

EmbreeScene::~EmbreeScene() {
    if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
}

PrimitiveHit EmbreeScene::intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.tnear = ray.t_min;
    rh.ray.dir_x = ray.direction.x;
    rh.ray.dir_y = ray.direction.y;
    rh.ray.dir_z = ray.direction.z;
    rh.ray.time = 0.0f;
    rh.ray.tfar = ray.t_max;
    rh.ray.mask = std::numeric_limits<unsigned>::max();
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
    return {rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID};
}

bool EmbreeScene::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
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
    rtcOccluded1(impl_->scene, &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

std::size_t EmbreeScene::memory_bytes() const { return impl_->bytes; }

#endif

}  // namespace librt::bench
