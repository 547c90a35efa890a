#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>

namespace librt {
namespace {

std::vector<Triangle> mesh_triangles(const TriangleMesh& mesh) {
    std::vector<Triangle> tris(mesh.triangle_count());
    for (std::size_t i = 0; i < tris.size(); ++i) tris[i] = mesh.triangle(i);
    return tris;
}

/// Leaf callback shared by the BVH and the linear scan: tests the triangle in a slot
/// and records it as the nearest so far.
struct NearestTriangle {
    const Triangle* triangles;
    const std::uint32_t* ids;  // slot -> caller's triangle index; null means identity
    WatertightRay prepared;
    PrimitiveHit hit;

    bool operator()(std::uint32_t slot, Ray& ray) {
        const auto h = librt::intersect(triangles[slot], prepared, ray.t_min, ray.t_max);
        if (!h) return false;
        ray.t_max = h->t;
        hit = {h->t, h->u, h->v, ids ? ids[slot] : slot};
        return true;
    }
};

}  // namespace

TriangleBvh::TriangleBvh(const TriangleMesh& mesh, BvhBuilder builder) {
    build(mesh_triangles(mesh), builder);
}

TriangleBvh::TriangleBvh(std::span<const Triangle> triangles, BvhBuilder builder) {
    build(triangles, builder);
}

void TriangleBvh::build(std::span<const Triangle> triangles, BvhBuilder builder) {
    std::vector<BBox> boxes(triangles.size());
    std::vector<glm::vec3> centers(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        boxes[i] = librt::bounds(triangles[i]);
        centers[i] = boxes[i].center();
    }
    bvh_ = build_bvh(builder, boxes, centers);
    triangles_.resize(triangles.size());
    for (std::size_t slot = 0; slot < triangles.size(); ++slot)
        triangles_[slot] = triangles[bvh_.prim_indices[slot]];
}

PrimitiveHit TriangleBvh::intersect(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle nearest{triangles_.data(), bvh_.prim_indices.data(), prepare_watertight(ray), {}};
    traverse<false>(bvh_, r, nearest);
    return nearest.hit;
}

bool TriangleBvh::occluded(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle any{triangles_.data(), nullptr, prepare_watertight(ray), {}};
    return traverse<true>(bvh_, r, any);
}

std::size_t TriangleBvh::memory_bytes() const {
    return bvh_.memory_bytes() + triangles_.size() * sizeof(Triangle);
}

TriangleList::TriangleList(const TriangleMesh& mesh) : triangles_(mesh_triangles(mesh)) {}

TriangleList::TriangleList(std::span<const Triangle> triangles)
    : triangles_(triangles.begin(), triangles.end()) {}

PrimitiveHit TriangleList::intersect(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle nearest{triangles_.data(), nullptr, prepare_watertight(ray), {}};
    traverse_linear<false>(static_cast<std::uint32_t>(triangles_.size()), r, nearest);
    return nearest.hit;
}

bool TriangleList::occluded(const Ray& ray) const {
    Ray r = ray;
    NearestTriangle any{triangles_.data(), nullptr, prepare_watertight(ray), {}};
    return traverse_linear<true>(static_cast<std::uint32_t>(triangles_.size()), r, any);
}

}  // namespace librt
