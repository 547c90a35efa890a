#include <librt/core/error.h>
#include <librt/geometry/mesh.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <string>

using namespace librt;

namespace {

/// Two triangles of the unit square in z = 0 with +z normals and uvs.
TriangleMesh make_square() {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

/// The Error message validate() throws, or "" if it does not throw.
std::string validate_message(const TriangleMesh& m) {
    try {
        validate(m);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Mesh, BoundsCoverAllPositions) {
    const BBox b = make_square().bounds();
    expect_near(b.lo, {0, 0, 0});
    expect_near(b.hi, {1, 1, 0});
    EXPECT_TRUE(TriangleMesh{}.bounds().empty());
}

TEST(Mesh, MakeTransformScalesThenRotatesThenTranslates) {
    // Scale x by 2, rotate 90 degrees about z (x -> y), then translate.
    const glm::mat4 m = make_transform({2, 1, 1}, {0, 0, 90}, {0, -10, 0});
    expect_near(glm::vec3(m * glm::vec4(1, 0, 0, 1)), {0, -8, 0});
    // Rotations apply about x first, then y: x 90 takes y to z, y 90 takes z to x.
    const glm::mat4 r = make_transform(glm::vec3(1), {90, 90, 0}, glm::vec3(0));
    expect_near(glm::vec3(r * glm::vec4(0, 1, 0, 1)), {1, 0, 0});
    // The report's bunny placement.
    const glm::mat4 bunny = make_transform(glm::vec3(20), glm::vec3(0), {0, -10, 0});
    expect_near(glm::vec3(bunny * glm::vec4(0.5f, 0.5f, 0.5f, 1)), {10, 0, 10});
}

TEST(Mesh, TransformMovesPositionsAndKeepsUnitNormals) {
    TriangleMesh m = make_square();
    transform(m, make_transform(glm::vec3(3), {90, 0, 0}, {1, 2, 3}));
    // Rotating 90 degrees about x takes y to z and z to -y.
    expect_near(m.positions[2], glm::vec3(3, 0, 3) + glm::vec3(1, 2, 3));
    for (const glm::vec3& n : m.normals) expect_near(n, {0, -1, 0});
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));  // no mirror: winding unchanged
}

TEST(Mesh, NormalsStayPerpendicularUnderNonUniformScale) {
    // A 45-degree slope: the normal (-1, 1, 0)/sqrt2. Scaling x by 4 flattens the slope,
    // so the true normal tilts towards +y; scaling the normal itself would tilt it away.
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}};
    m.normals.assign(3, glm::normalize(glm::vec3(-1, 1, 0)));
    transform(m, make_transform({4, 1, 1}, glm::vec3(0), glm::vec3(0)));
    const glm::vec3 tangent = m.positions[1] - m.positions[0];
    for (const glm::vec3& n : m.normals) {
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(n, tangent), 0.0f, 1e-6f);
        expect_near(n, glm::normalize(glm::vec3(-1, 4, 0)));
    }
}

TEST(Mesh, MirrorSwapsWindingToMatchNormals) {
    TriangleMesh m = make_square();
    transform(m, make_transform({1, 1, -1}, glm::vec3(0), glm::vec3(0)));
    for (const glm::vec3& n : m.normals) expect_near(n, {0, 0, -1});
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        EXPECT_GT(glm::dot(area_normal(m.triangle(i)), m.normals[0]), 0.0f);
    }
}

TEST(Mesh, TransformRejectsProjectiveAndSingularMatrices) {
    TriangleMesh m = make_square();
    glm::mat4 projective(1.0f);
    projective[2][3] = 1.0f;
    EXPECT_THROW(transform(m, projective), Error);
    EXPECT_THROW(transform(m, make_transform({1, 0, 1}, glm::vec3(0), glm::vec3(0))), Error);
    m.normals.clear();  // without normals, flattening is allowed
    transform(m, make_transform({1, 1, 0}, glm::vec3(0), glm::vec3(0)));
    EXPECT_EQ(m.bounds().diagonal().z, 0.0f);
}

TEST(Mesh, ValidateAcceptsAGoodMesh) {
    TriangleMesh m = make_square();
    EXPECT_NO_THROW(validate(m));
    m.materials.resize(1);
    m.material_ids = {0, 0};
    EXPECT_NO_THROW(validate(m));
    EXPECT_NO_THROW(validate(TriangleMesh{}));
}

TEST(Mesh, ValidateNamesTheBadIndex) {
    TriangleMesh m = make_square();
    m.triangles[1].z = 4;
    const std::string msg = validate_message(m);
    EXPECT_NE(msg.find("triangle 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("index 4"), std::string::npos) << msg;
}

TEST(Mesh, ValidateRejectsWrongArrayLengths) {
    TriangleMesh m = make_square();
    m.normals.pop_back();
    EXPECT_NE(validate_message(m).find("normals"), std::string::npos);
    m = make_square();
    m.uvs.push_back({});
    EXPECT_NE(validate_message(m).find("uvs"), std::string::npos);
    m = make_square();
    m.materials.resize(1);
    m.material_ids = {0};
    EXPECT_NE(validate_message(m).find("material ids"), std::string::npos);
    m.material_ids = {0, 1};
    EXPECT_NE(validate_message(m).find("material id 1"), std::string::npos);
}

TEST(Mesh, ValidateRejectsNonFinitePositions) {
    TriangleMesh m = make_square();
    m.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(validate_message(m).find("position 3"), std::string::npos);
    m = make_square();
    m.positions[2].x = std::numeric_limits<float>::infinity();
    EXPECT_NE(validate_message(m).find("position 2"), std::string::npos);
    m = make_square();
    m.normals[1].z = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(validate_message(m).find("normal 1"), std::string::npos);
}
