// The display transform of rt_render's PNGs (core/tone_curve.h, issue 42 item 6): the clamp
// curve is the identity on [0, 1]; the filmic ACES curve keeps 0 black, shows mid grey as the
// clamp does, is monotonic and bounded, keeps greys grey and rolls highlights off below
// white; auto exposure puts the log-average luminance at mid grey (Reinhard et al. 2002).

#include <librt/core/error.h>
#include <librt/core/tone_curve.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace librt;

TEST(ToneCurve, ClampIsTheIdentityOnTheUnitRangeAndCutsOutsideIt) {
    for (float v : {0.0f, 0.001f, 0.18f, 0.5f, 1.0f}) {
        EXPECT_EQ(apply_tone_curve(ToneCurve::Clamp, glm::vec3(v)), glm::vec3(v));
    }
    EXPECT_EQ(apply_tone_curve(ToneCurve::Clamp, glm::vec3(7.0f, -1.0f, NAN)),
              glm::vec3(1.0f, 0.0f, 0.0f));
}

TEST(ToneCurve, AcesKeepsBlackAndMidGreyRollsOffAndStaysInRange) {
    EXPECT_EQ(apply_tone_curve(ToneCurve::Aces, glm::vec3(0.0f)), glm::vec3(0.0f));
    // Mid grey is shown as the clamp shows it (the gain solves the fit's quadratic); the
    // matrices' rows sum to 1 to 5 digits, so a grey stays grey to that.
    const glm::vec3 grey = apply_tone_curve(ToneCurve::Aces, glm::vec3(0.18f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey[c], 0.18f, 1e-4f);
    // Monotonic along the greys, below white for finite input, and near white far above 1.
    float last = 0.0f;
    for (float v = 1e-3f; v < 1e4f; v *= 1.1f) {
        const float y = apply_tone_curve(ToneCurve::Aces, glm::vec3(v)).y;
        EXPECT_GE(y, last) << v;
        EXPECT_LE(y, 1.0f) << v;
        last = y;
    }
    EXPECT_GT(last, 0.99f);
    // A highlight of 1 (display white under the clamp) is rolled off below white.
    const float white = apply_tone_curve(ToneCurve::Aces, glm::vec3(1.0f)).y;
    EXPECT_GT(white, 0.6f);
    EXPECT_LT(white, 0.9f);
    // Bad values: NaN and negative as 0, +inf as the curve's white, never outside [0, 1].
    const float inf = std::numeric_limits<float>::infinity();
    const glm::vec3 odd = apply_tone_curve(ToneCurve::Aces, glm::vec3(NAN, -5.0f, inf));
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(odd[c], 0.0f);
        EXPECT_LE(odd[c], 1.0f);
    }
    // A saturated bright light desaturates toward white (its other channels rise).
    const glm::vec3 red = apply_tone_curve(ToneCurve::Aces, glm::vec3(50.0f, 0.0f, 0.0f));
    EXPECT_GT(red.x, 0.95f);
    EXPECT_GT(red.y, 0.0f);
}

TEST(ToneCurve, DisplayEncodeIsTheCurveThenSrgb) {
    Image image(2, 1);
    image.at(0, 0) = glm::vec3(0.09f);  // times 2 = mid grey
    image.at(1, 0) = glm::vec3(0.001f);
    const Image out = display_encode(image, 2.0f, ToneCurve::Aces);
    const float g = apply_tone_curve(ToneCurve::Aces, glm::vec3(0.18f)).x;
    EXPECT_FLOAT_EQ(out.at(0, 0).x, 1.055f * std::pow(g, 1.0f / 2.4f) - 0.055f);
    // The linear segment of sRGB below 0.0031308.
    EXPECT_FLOAT_EQ(srgb_encode(0.002f), 12.92f * 0.002f);
    EXPECT_THROW((void)display_encode(image, -1.0f, ToneCurve::Clamp), Error);
    EXPECT_THROW((void)display_encode(image, NAN, ToneCurve::Clamp), Error);
    EXPECT_EQ(to_string(ToneCurve::Aces), "aces");
    EXPECT_EQ(to_string(ToneCurve::Clamp), "clamp");
}

TEST(ToneCurve, AutoExposurePutsTheLogAverageAtMidGrey) {
    // Half the pixels at luminance 0.02, half at 2: log-average sqrt((0.02+1e-4)(2+1e-4)).
    Image image(4, 2);
    for (int x = 0; x < 4; ++x) {
        image.at(x, 0) = glm::vec3(0.02f);
        image.at(x, 1) = glm::vec3(2.0f);
    }
    image.at(0, 0) = glm::vec3(NAN);  // skipped, with one of the bright ones to stay even
    image.at(0, 1) = glm::vec3(std::numeric_limits<float>::infinity());
    const double mean = std::sqrt((0.02 + 1e-4) * (2.0 + 1e-4));
    EXPECT_NEAR(auto_exposure_scale(image), 0.18 / mean, 1e-4 * 0.18 / mean);
    // Nothing finite: 1; black: 0.18 / 1e-4.
    Image nan(1, 1);
    nan.at(0, 0) = glm::vec3(NAN);
    EXPECT_EQ(auto_exposure_scale(nan), 1.0f);
    Image black(1, 1);
    EXPECT_EQ(auto_exposure_scale(black), 1800.0f);
}
