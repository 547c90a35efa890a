#include <librt/core/finite.h>

#include <gtest/gtest.h>

#include <glm/ext/vector_double3.hpp>

#include <limits>

namespace librt {
namespace {

TEST(Finite, EveryComponentMustBeFinite) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    constexpr float big = std::numeric_limits<float>::max();
    constexpr float tiny = std::numeric_limits<float>::denorm_min();
    EXPECT_TRUE(finite(glm::vec3(0.0f, -big, tiny)));
    EXPECT_TRUE(finite(glm::vec2(big, -0.0f)));
    for (int i = 0; i < 3; ++i) {
        for (const float bad : {inf, -inf, nan}) {
            glm::vec3 v(1.0f);
            v[i] = bad;
            EXPECT_FALSE(finite(v)) << "component " << i << " = " << bad;
            if (i < 2) {
                glm::vec2 w(1.0f);
                w[i] = bad;
                EXPECT_FALSE(finite(w)) << "component " << i << " = " << bad;
            }
        }
    }
    // Doubles too: a value beyond float's range is still a finite double.
    EXPECT_TRUE(finite(glm::dvec3(1e300, 0.0, -1e300)));
    EXPECT_FALSE(finite(glm::dvec3(0.0, std::numeric_limits<double>::infinity(), 0.0)));
}

}  // namespace
}  // namespace librt
