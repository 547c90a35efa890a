#include <librt/accel/top_level.h>
#include <librt/core/error.h>
#include <librt/geometry/procedural.h>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace librt {
namespace {

// Placing one prototype many times stores its triangles and BVH once: the instances add
// only their matrices and the structure over them, a few hundred bytes each.
TEST(TopLevel, InstancesShareTheirPrototype) {
    const TriangleMesh mesh = make_teapot(16);  // 16k triangles
    TopLevel single;
    single.add_mesh(single.add_prototype(mesh));
    single.build();

    TopLevel many;
    const std::uint32_t proto = many.add_prototype(mesh);
    constexpr int kInstances = 64;
    for (int k = 0; k < kInstances; ++k)
        many.add_instance(proto,
                          glm::translate(glm::mat4(1.0f), glm::vec3(10.0f * float(k), 0, 0)));
    many.build();
    EXPECT_EQ(many.instance_count(), std::size_t(kInstances));
    EXPECT_EQ(many.prototype_count(), 1u);
    // Per instance: the instance record, the object, a top-level node pair and index.
    const std::size_t per_instance_bound = 512;
    EXPECT_LE(many.memory_bytes(), single.memory_bytes() + kInstances * per_instance_bound);
    EXPECT_GT(many.memory_bytes(), single.memory_bytes());
}

// The flat list (at most kFlatObjectLimit objects) and the top-level BVH beyond it find the
// same hits as testing every object in turn.
TEST(TopLevel, FlatListAndBvhAgreeWithBruteForce) {
    for (const std::uint32_t count : {TopLevel::kFlatObjectLimit, TopLevel::kFlatObjectLimit + 9}) {
        std::mt19937 rng(count);
        std::uniform_real_distribution<float> U(-10.0f, 10.0f);
        TopLevel top;
        std::vector<TopLevel> singles(count);
        const std::uint32_t proto = top.add_prototype(make_icosphere({0, 0, 0}, 1.0f, 2));
        for (std::uint32_t i = 0; i < count; ++i) {
            if (i % 3 == 0) {
                const Sphere s{{U(rng), U(rng), U(rng)}, 0.5f + 0.1f * std::fabs(U(rng))};
                top.add_sphere(s);
                singles[i].add_sphere(s);
            } else {
                const glm::mat4 m =
                    glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(U(rng), U(rng), U(rng))),
                               glm::vec3(1.0f, 0.5f, i % 2 ? -1.5f : 1.5f));
                if (i % 3 == 1) {
                    top.add_instance(proto, m);
                    singles[i].add_instance(
                        singles[i].add_prototype(make_icosphere({0, 0, 0}, 1, 2)), m);
                } else {
                    TriangleMesh baked = make_icosphere({0, 0, 0}, 1.0f, 2);
                    transform(baked, m);
                    top.add_mesh(top.add_prototype(baked));
                    singles[i].add_mesh(singles[i].add_prototype(std::move(baked)));
                }
            }
            singles[i].build();
        }
        top.build();
        int hits = 0;
        for (int r = 0; r < 20000; ++r) {
            Ray ray{{U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}};
            ObjectHit hit;
            const bool found = top.intersect(ray, hit);
            float best = ray.t_max;
            std::uint32_t best_object = kInvalidId;
            for (std::uint32_t i = 0; i < count; ++i) {
                ObjectHit h;
                if (singles[i].intersect(ray, h) && h.primitive.t < best) {
                    best = h.primitive.t;
                    best_object = i;
                }
            }
            ASSERT_EQ(found, best_object != kInvalidId) << "ray " << r;
            EXPECT_EQ(top.occluded(ray), found) << "ray " << r;
            if (!found) continue;
            ++hits;
            EXPECT_EQ(hit.object_id, best_object) << "ray " << r;
            EXPECT_EQ(hit.primitive.t, best) << "ray " << r;
            // Ignoring the object hit leaves exactly the others.
            bool others = false;
            for (std::uint32_t i = 0; i < count; ++i) {
                ObjectHit h;
                others |= i != best_object && singles[i].intersect(ray, h);
            }
            EXPECT_EQ(top.occluded(ray, best_object), others) << "ray " << r;
            // The closest hit ignoring that object is the nearest of the others; ignoring
            // no object (kInvalidId) it is the hit itself.
            float second = ray.t_max;
            std::uint32_t second_object = kInvalidId;
            for (std::uint32_t i = 0; i < count; ++i) {
                ObjectHit h;
                if (i != best_object && singles[i].intersect(ray, h) && h.primitive.t < second) {
                    second = h.primitive.t;
                    second_object = i;
                }
            }
            Hit other;
            ASSERT_EQ(top.intersect_ignoring(ray, other, best_object), others) << "ray " << r;
            if (others) {
                EXPECT_EQ(other.object_id, second_object) << "ray " << r;
                EXPECT_EQ(other.t, second) << "ray " << r;
            }
            Hit same;
            ASSERT_TRUE(top.intersect_ignoring(ray, same, kInvalidId)) << "ray " << r;
            EXPECT_EQ(same.object_id, best_object) << "ray " << r;
            EXPECT_EQ(same.t, best) << "ray " << r;
        }
        EXPECT_GT(hits, 1000);
    }
}

// A shadow ray's ignored object is dropped from the flat list before the visit (its box's
// bit): for every ignored id (each object, an unknown id, kInvalidId) the answer is whether
// any other object is hit, as testing every object in turn says.
TEST(TopLevel, OccludedIgnoresExactlyItsObjectInTheFlatList) {
    constexpr std::uint32_t kCount = 11;  // the synthesis' size: flat, spheres and meshes
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(-6.0f, 6.0f);
    TopLevel top;
    std::vector<TopLevel> singles(kCount);
    for (std::uint32_t i = 0; i < kCount; ++i) {
        if (i % 4 != 3) {
            const Sphere s{{U(rng), U(rng), U(rng)}, 1.0f + 0.2f * std::fabs(U(rng))};
            top.add_sphere(s);
            singles[i].add_sphere(s);
        } else {
            TriangleMesh mesh = make_icosphere({U(rng), U(rng), U(rng)}, 1.5f, 2);
            top.add_mesh(top.add_prototype(mesh));
            singles[i].add_mesh(singles[i].add_prototype(std::move(mesh)));
        }
        singles[i].build();
    }
    top.build();
    int occluded_by_others_only = 0;
    for (int r = 0; r < 20000; ++r) {
        const Ray ray{
            {U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}, 0.0f, 0.5f + std::fabs(U(rng))};
        bool hit[kCount];
        for (std::uint32_t i = 0; i < kCount; ++i) {
            ObjectHit h;
            hit[i] = singles[i].intersect(ray, h);
        }
        for (std::uint32_t ignored = 0; ignored < kCount + 2; ++ignored) {
            const std::uint32_t id = ignored == kCount + 1 ? kInvalidId : ignored;
            bool others = false;
            for (std::uint32_t i = 0; i < kCount; ++i) others |= hit[i] && i != id;
            EXPECT_EQ(top.occluded(ray, id), others) << "ray " << r << " ignoring " << id;
            occluded_by_others_only += id < kCount && hit[id] && others;
        }
    }
    // The ignored object itself is often in the way while another one is too.
    EXPECT_GT(occluded_by_others_only, 400);
}

// A flat list of spheres only answers its closest-hit queries from every root at once;
// ignoring an object goes through the box visit instead and must give the same nearest.
TEST(TopLevel, IntersectIgnoringInAListOfSpheresOnly) {
    TopLevel top;
    for (int i = 0; i < 3; ++i) top.add_sphere(Sphere{{3.0f * float(i), 0, 0}, 1.0f});
    top.build();
    const Ray ray{{-5, 0, 0}, {1, 0, 0}};
    Hit hit;
    ASSERT_TRUE(top.intersect_ignoring(ray, hit, 0));
    EXPECT_EQ(hit.object_id, 1u);
    EXPECT_FLOAT_EQ(hit.t, 7.0f);
    ASSERT_TRUE(top.intersect_ignoring(ray, hit, 1));
    EXPECT_EQ(hit.object_id, 0u);
    EXPECT_FLOAT_EQ(hit.t, 4.0f);
    const Ray past{{-5, 0, 0}, {1, 0, 0}, 9.5f};  // t_min past the first two spheres
    ASSERT_TRUE(top.intersect_ignoring(past, hit, 1));
    EXPECT_EQ(hit.object_id, 2u);
    EXPECT_FLOAT_EQ(hit.t, 10.0f);
    EXPECT_FALSE(top.intersect_ignoring(past, hit, 2));
}

// One object skips the box test (its own test rejects what the box would): every answer
// equals the same object's in a two-object list, where the boxes are tested, for a sphere,
// a mesh and an instance, with rays that miss, start inside, or end short of the object.
TEST(TopLevel, OneObjectAnswersAsTheBoxedList) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(-3.0f, 3.0f);
    const glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, 0.1f)),
                                   glm::vec3(1.0f, 0.5f, -1.5f));
    for (int kind = 0; kind < 3; ++kind) {
        TopLevel one, two;
        for (TopLevel* top : {&one, &two}) {
            if (kind == 0) {
                top->add_sphere(Sphere{{0.2f, 0.1f, -0.3f}, 1.2f});
            } else {
                const std::uint32_t proto = top->add_prototype(make_icosphere({0, 0, 0}, 1.0f, 2));
                if (kind == 1)
                    top->add_mesh(proto);
                else
                    top->add_instance(proto, m);
            }
        }
        two.add_sphere(Sphere{{1e4f, 1e4f, 1e4f}, 1e-3f});  // far and tiny: never hit
        one.build();
        two.build();
        int hits = 0;
        for (int r = 0; r < 20000; ++r) {
            const Ray ray{{U(rng), U(rng), U(rng)},
                          {U(rng), U(rng), U(rng)},
                          r % 5 == 0 ? std::fabs(U(rng)) : 0.0f,
                          r % 7 == 0 ? std::fabs(U(rng)) : std::numeric_limits<float>::infinity()};
            ObjectHit a, b;
            const bool found = one.intersect(ray, a);
            ASSERT_EQ(found, two.intersect(ray, b)) << "kind " << kind << " ray " << r;
            EXPECT_EQ(one.occluded(ray), found) << "kind " << kind << " ray " << r;
            EXPECT_FALSE(one.occluded(ray, 0)) << "kind " << kind << " ray " << r;
            if (!found) continue;
            ++hits;
            EXPECT_EQ(a.object_id, b.object_id);
            EXPECT_EQ(a.primitive.t, b.primitive.t) << "kind " << kind << " ray " << r;
            EXPECT_EQ(a.primitive.primitive_id, b.primitive.primitive_id);
            EXPECT_EQ(a.primitive.u, b.primitive.u);
            EXPECT_EQ(a.primitive.v, b.primitive.v);
            Hit ignoring;
            EXPECT_FALSE(one.intersect_ignoring(ray, ignoring, 0));
        }
        EXPECT_GT(hits, 800) << "kind " << kind;
        // A ray that is not traceable (NaN) finds nothing, as in the list.
        const Ray bad{{std::nanf(""), 0, 0}, {1, 0, 0}};
        ObjectHit h;
        EXPECT_FALSE(one.intersect(bad, h));
        EXPECT_FALSE(one.occluded(bad));
    }
}

TEST(TopLevel, InstanceIdsAndBadInput) {
    TopLevel top;
    EXPECT_THROW((void)top.add_mesh(0), Error);
    EXPECT_THROW((void)top.add_instance(0, glm::mat4(1.0f)), Error);
    const std::uint32_t proto = top.add_prototype(make_box({-1, -1, -1}, {1, 1, 1}));
    top.add_sphere({{0, 0, 10}, 1});
    const std::uint32_t inst =
        top.add_instance(proto, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -10)));
    EXPECT_EQ(inst, 1u);
    EXPECT_EQ(top.instance_object(0), inst);
    EXPECT_EQ(top.kind(inst), ObjectKind::Instance);
    EXPECT_EQ(top.prototype_of(inst), proto);
    EXPECT_EQ(top.prototype_of(0), kInvalidId);
    const Ray ray{{0, 0, 0}, {0, 0, -2}};
    ObjectHit h;
    EXPECT_THROW((void)top.intersect(ray, h), Error);
    top.build();
    ASSERT_TRUE(top.intersect(ray, h));
    EXPECT_EQ(h.object_id, inst);
    EXPECT_FLOAT_EQ(h.primitive.t, 4.5f);  // the box's face at z = -9, direction length 2
    Hit hit;
    top.finish(ray, h, false, hit);
    EXPECT_EQ(hit.instance_id, 0u);
    EXPECT_NEAR(hit.point.z, -9.0f, 1e-5f);
    EXPECT_NEAR(hit.geometric_normal.z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace librt
