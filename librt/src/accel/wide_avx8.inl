// The 8-lane wide-BVH kernel shared by the AVX2 and AVX-512 files, which include it inside
// their own namespace and target pragma after defining LIBRT_WIDE_HIT_MASK(enter, exit): the
// only difference between the two, how the 8 lane compares become a bit mask.
struct Kernel : Block4Kernel {
    /// Per-ray constants of the slab test, broadcast; see wide_scalar.cpp.
    struct NodeRay {
        __m256 o[3];
        __m256 inv[3];
        std::uint32_t near[3];
        std::uint32_t far[3];
    };

    static NodeRay prepare_nodes(const Ray& ray) {
        NodeRay r;
        alignas(16) float inv[4];
        _mm_store_ps(inv, safe_inverse4(ray.direction));
        for (std::uint32_t a = 0; a < 3; ++a) {
            const float inv_a = inv[a];
            r.o[a] = _mm256_set1_ps(ray.origin[static_cast<int>(a)]);
            r.inv[a] = _mm256_set1_ps(inv_a);
            const bool negative = std::signbit(inv_a);
            r.near[a] = 2 * a + (negative ? 1 : 0);
            r.far[a] = 2 * a + (negative ? 0 : 1);
        }
        return r;
    }

    /// Slab test (Kay-Kajiya): t = (plane - o) / d per axis; enter = max of the near
    /// planes and t_min, exit = min of the far planes and t_max; hit when enter <= exit.
    static std::uint32_t intersect_node(const WideBvhNode& node, const NodeRay& r, float t_min,
                                        float t_max, float* t_enter) {
        __m256 tn[3], tf[3];
        for (std::uint32_t a = 0; a < 3; ++a) {
            tn[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.near[a]]), r.o[a]),
                                  r.inv[a]);
            tf[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(node.bounds[r.far[a]]), r.o[a]),
                                  r.inv[a]);
        }
        const __m256 enter =
            _mm256_max_ps(_mm256_max_ps(tn[0], tn[1]), _mm256_max_ps(tn[2], _mm256_set1_ps(t_min)));
        const __m256 exit =
            _mm256_min_ps(_mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(tf[0], tf[1]), tf[2]),
                                        _mm256_set1_ps(kSlabExitScale)),
                          _mm256_set1_ps(t_max));
        _mm256_store_ps(t_enter, enter);
        return LIBRT_WIDE_HIT_MASK(enter, exit);
    }
};

#include "wide_traversal.inl"

}  // namespace

PrimitiveHit intersect(const WideBvh& bvh, const Ray& ray) {
    return intersect_with<Kernel>(bvh, ray);
}
bool occluded(const WideBvh& bvh, const Ray& ray) { return occluded_with<Kernel>(bvh, ray); }
