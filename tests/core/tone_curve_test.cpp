// The display transform of rt_render's PNGs (core/tone_curve.h, issue 42 item 6): the clamp
// curve is the identity on [0, 1]; the filmic ACES curve keeps 0 black, shows mid grey as the
// clamp does, is monotonic and bounded, keeps greys grey and rolls highlights off below
// white; AgX keeps black, shows mid grey as the clamp does with the slope its sigmoid sets,
// is monotone in each channel, keeps greys grey and saturates to white; auto exposure puts
// the log-average luminance at mid grey (Reinhard et al. 2002).

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

// AgX (tone_curve.h): properties that follow from its construction, not from earlier output.
TEST(ToneCurve, AgxKeepsBlackAndShowsMidGreyAsClampDoes) {
    EXPECT_EQ(apply_tone_curve(ToneCurve::Agx, glm::vec3(0.0f)), glm::vec3(0.0f));
    // At or below the bottom of the log range (10 stops under mid grey) everything is black.
    EXPECT_EQ(apply_tone_curve(ToneCurve::Agx, glm::vec3(0.18f * std::exp2(-10.5f))),
              glm::vec3(0.0f));
    // Mid grey is the sigmoid's pivot, whose display value decodes to 0.18; the outset keeps
    // a grey grey.
    const glm::vec3 grey = apply_tone_curve(ToneCurve::Agx, glm::vec3(0.18f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey[c], 0.18f, 1e-6f);
    // The slope at mid grey: the sigmoid's 2.4 per unit of the 16.5-stop log range, through
    // the 2.4 exponent, d/dstops (y^2.4) = 2.4 y^1.4 * 2.4 / 16.5 at y = 0.18^(1/2.4).
    // A central difference over 0.01 stops either side: the limbs' curvature (which grows as
    // (s dx)^1.5 from the pivot) and float rounding stay below 1e-4 of the slope there.
    const float h = 0.01f;
    const float up = apply_tone_curve(ToneCurve::Agx, glm::vec3(0.18f * std::exp2(h))).y;
    const float down = apply_tone_curve(ToneCurve::Agx, glm::vec3(0.18f * std::exp2(-h))).y;
    const double slope = 2.4 * std::pow(0.18, 1.4 / 2.4) * 2.4 / 16.5;
    EXPECT_NEAR((up - down) / (2.0 * h), slope, 1e-3 * slope);
}

TEST(ToneCurve, AgxSaturatesToWhiteAndStaysInRange) {
    const float inf = std::numeric_limits<float>::infinity();
    // 6.5 stops above mid grey is the top of the range: white (within rounding), never above.
    for (const glm::vec3 v : {glm::vec3(0.18f * std::exp2(6.5f)), glm::vec3(1e30f), glm::vec3(inf),
                              glm::vec3(1e9f, 0.0f, 0.0f), glm::vec3(0.0f, inf, 0.0f)}) {
        const glm::vec3 y = apply_tone_curve(ToneCurve::Agx, v);
        for (int c = 0; c < 3; ++c) {
            EXPECT_LE(y[c], 1.0f) << v.x << ' ' << v.y << ' ' << v.z;
            EXPECT_NEAR(y[c], 1.0f, 1e-5f) << v.x << ' ' << v.y << ' ' << v.z;
        }
    }
    // NaN and negative count as 0.
    EXPECT_EQ(apply_tone_curve(ToneCurve::Agx, glm::vec3(NAN, -5.0f, 0.0f)), glm::vec3(0.0f));
    const glm::vec3 odd = apply_tone_curve(ToneCurve::Agx, glm::vec3(NAN, -5.0f, 3.0f));
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(odd[c], 0.0f);
        EXPECT_LE(odd[c], 1.0f);
    }
}

TEST(ToneCurve, AgxIsMonotoneInEachChannelAndKeepsGreysGrey) {
    for (const float other : {0.0f, 0.05f, 1.0f, 20.0f}) {
        for (int c = 0; c < 3; ++c) {
            float last = -1.0f;
            for (float v = 1e-5f; v < 1e5f; v *= 1.05f) {
                glm::vec3 in(other);
                in[c] = v;
                const float y = apply_tone_curve(ToneCurve::Agx, in)[c];
                EXPECT_GE(y, last) << "channel " << c << " = " << v << ", others " << other;
                EXPECT_GE(y, 0.0f);
                EXPECT_LE(y, 1.0f);
                last = y;
            }
        }
    }
    // Along the greys: strictly increasing inside the log range, and neutral.
    float last = -1.0f;
    for (float v = 0.18f * std::exp2(-9.9f); v < 0.18f * std::exp2(6.4f); v *= 1.05f) {
        const glm::vec3 y = apply_tone_curve(ToneCurve::Agx, glm::vec3(v));
        EXPECT_GT(y.y, last) << v;
        EXPECT_NEAR(y.x, y.y, 1e-6f) << v;
        EXPECT_NEAR(y.z, y.y, 1e-6f) << v;
        last = y.y;
    }
    // Two equal channels stay equal (the inset and outset pull every channel toward one
    // grey, and the curve is the same on each): a bright red passes to white through pinks,
    // not skewed toward yellow, and still brightens.
    float red_last = 0.0f;
    for (const float v : {1.0f, 4.0f, 16.0f, 50.0f}) {
        const glm::vec3 y = apply_tone_curve(ToneCurve::Agx, glm::vec3(v, 0.1f, 0.1f));
        EXPECT_EQ(y.y, y.z) << v;
        EXPECT_GT(y.x, y.y) << v;
        EXPECT_GE(y.y, red_last) << v;
        red_last = y.y;
    }
}

TEST(ToneCurve, AgxIsDeterministicAndNamed) {
    Image image(3, 2);
    for (int i = 0; i < 6; ++i) {
        const float f = float(i);
        image.pixels[i] = glm::vec3(0.01f * f, 0.7f * f, 3.0f / (f + 1.0f));
    }
    const Image a = display_encode(image, 1.5f, ToneCurve::Agx);
    const Image b = display_encode(image, 1.5f, ToneCurve::Agx);
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(a.pixels[i], b.pixels[i]);
        const glm::vec3 d = apply_tone_curve(ToneCurve::Agx, 1.5f * image.pixels[i]);
        EXPECT_EQ(a.pixels[i], glm::vec3(srgb_encode(d.x), srgb_encode(d.y), srgb_encode(d.z)));
    }
    EXPECT_EQ(to_string(ToneCurve::Agx), "agx");
}
