// The illustrative enhancers (core/appearance/Enhancers.glsl) against the thesis formulas, worked by
// hand for chosen samples; the tool parameters' validation and JSON round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/appearance/Enhancers.h"
#include "core/base/Error.h"

using namespace hvx;
using namespace hvx::core::glsl;

namespace {
HvxSample sample(glm::vec3 p, glm::vec3 v, glm::vec3 g, float gn, float a) {
    HvxSample x;
    x.p = p;
    x.v = v;
    x.g = g;
    x.gn = gn;
    x.s = 100;
    x.c = {0.8f, 0.6f, 0.4f};
    x.a = a;
    x.lit = 1;
    x.importance = 1;
    return x;
}
}  // namespace

TEST(Enhancers, SmoothstepPqNormAndDistanceWeightFollowEquations62To69) {
    EXPECT_FLOAT_EQ(hvxSmooth(0.2f, 0.6f, 0.1f), 0.0f);
    EXPECT_FLOAT_EQ(hvxSmooth(0.2f, 0.6f, 0.4f), 0.5f * 0.5f * (3 - 2 * 0.5f));  // Eq. 6.2 at the midpoint
    EXPECT_FLOAT_EQ(hvxSmooth(0.2f, 0.6f, 0.9f), 1.0f);
    EXPECT_NEAR(hvxPqNorm({0.6f, 0.8f, 0.0f}, 2, 2), 1.0f, 1e-6f);                  // sphere
    EXPECT_NEAR(hvxPqNorm({0.6f, 0.8f, 0.5f}, 2, 4), std::pow(1.0f + 0.0625f, 0.25f), 1e-6f);  // cylinder
    EXPECT_NEAR(hvxPqNorm({1.0f, 1.0f, 0.0f}, 4, 4), std::pow(2.0f, 0.25f), 1e-6f);  // rounded cube
    EXPECT_NEAR(hvxGBeta(0.5f, -2.0f), 0.5f / (std::exp(-1.0f) + 0.5f), 1e-6f);       // Eq. 6.9
    EXPECT_FLOAT_EQ(hvxFocusWeight(0.3f, 0.55f, -2.0f), 1.0f);                        // Eq. 6.8 inside rho
    EXPECT_NEAR(hvxFocusWeight(1.0f, 0.55f, -2.0f), 0.5f, 1e-6f);                      // 1 - g(1) = 1/2
    EXPECT_FLOAT_EQ(hvxFocusWeight(1.2f, 0.55f, -2.0f), 0.0f);
    EXPECT_FLOAT_EQ(hvxContextAngle(0.99f, 0.98f, 0.9f), 0.0f);                        // Eq. 6.16 in the focus cone
    EXPECT_NEAR(hvxContextAngle(0.94f, 0.98f, 0.9f), 1.0f - (0.94f - 0.98f) / (0.9f - 0.98f), 1e-6f);
}

TEST(Enhancers, ClipPlaneIsACutFaceOnContextObliqueAndEmphasisesTheSlab) {
    const glm::vec4 plane(0, 0, 1, -10);  // keeps z <= 10
    // Face-on (looking along -n): mu = smoothstep(1 - 1, fl, fh) = 0.
    auto x = sample({0, 0, 12}, {0, 0, -1}, {0, 0, 1}, 0.5f, 0.4f);
    hvxClip(x, plane, 4.0f, 0.3f, 0.9f);
    EXPECT_FLOAT_EQ(x.a, 0.0f);
    // Oblique at 60 degrees: -n.v = 0.5, mu = smoothstep(0.3, 0.9, 0.5).
    x = sample({0, 0, 12}, {std::sqrt(0.75f), 0, -0.5f}, {0, 0, 1}, 0.5f, 0.4f);
    hvxClip(x, plane, 4.0f, 0.3f, 0.9f);
    const float t = (0.5f - 0.3f) / 0.6f;
    EXPECT_NEAR(x.a, 0.4f * t * t * (3 - 2 * t), 1e-6f);
    // Parallel to the plane: full context.
    x = sample({0, 0, 12}, {1, 0, 0}, {0, 0, 1}, 0.5f, 0.4f);
    hvxClip(x, plane, 4.0f, 0.3f, 0.9f);
    EXPECT_FLOAT_EQ(x.a, 0.4f);
    // In the slab, halfway: opacity half way to 1, lighting half way to ambient + emission.
    x = sample({0, 0, 8}, {0, 0, -1}, {0, 0, 1}, 0.5f, 0.4f);
    hvxClip(x, plane, 4.0f, 0.3f, 0.9f);
    EXPECT_NEAR(x.a, 0.4f + 0.5f * 0.6f, 1e-6f);
    EXPECT_NEAR(x.lit, 0.5f, 1e-6f);
    // Behind the slab: untouched.
    x = sample({0, 0, 0}, {0, 0, -1}, {0, 0, 1}, 0.5f, 0.4f);
    hvxClip(x, plane, 4.0f, 0.3f, 0.9f);
    EXPECT_FLOAT_EQ(x.a, 0.4f);
    EXPECT_FLOAT_EQ(x.lit, 1.0f);
}

TEST(Enhancers, FocalProbeBlendsFocusAndContextStylesByEquation610) {
    // Inside rho (d = 1): pure focus, Eq. 6.12 with s_i from Eq. 6.11.
    auto x = sample({0, 0, 0}, {0, 0, -1}, {1, 0, 0}, 0.5f, 0.4f);  // gradient across the view: a silhouette
    const float w = hvxSmooth(0.015f, 0.95f, 0.5f);
    const float si = w * hvxSmooth(0.7f, 0.95f, 1.0f);
    hvxFocalProbe(x, 0.2f, 0.55f, -2.0f, 0.015f, 0.95f, 0.7f, 0.95f, 0.9f, 1.3f, 0.0f);
    EXPECT_NEAR(x.c.r, (1 - si) * 1.3f * 0.8f, 1e-6f);
    EXPECT_NEAR(x.a, 1.3f * 0.4f, 1e-6f);
    EXPECT_LT(x.lit, 0.0f);
    // Outside the probe (d = 0): context, alpha = h * s_i * lambda * alpha (Eq. 6.15).
    x = sample({0, 0, 0}, {0, 0, -1}, {1, 0, 0}, 0.5f, 0.4f);
    hvxFocalProbe(x, 1.5f, 0.55f, -2.0f, 0.015f, 0.95f, 0.7f, 0.95f, 0.9f, 1.3f, 0.6f);
    EXPECT_NEAR(x.c.g, 0.9f * 0.6f, 1e-6f);
    EXPECT_NEAR(x.a, 0.6f * si * 0.9f * 0.4f, 1e-6f);
    // Relief (Eqs 6.13-6.14): the light made perpendicular to the smoothed normal.
    const glm::vec3 L(0, 0, 1), g = glm::normalize(glm::vec3(1, 0, 1)), n(0, 0, 1);
    EXPECT_NEAR(hvxRelief(L, g, n, 0.35f, 0.65f, 3.0f), 0.35f + 0.65f * (glm::dot(L, g) + 3.0f * 0.0f), 1e-6f);
    const glm::vec3 n2 = glm::normalize(glm::vec3(0, 1, 1));
    const glm::vec3 Lstar = L - n2 * glm::dot(n2, L);
    EXPECT_NEAR(hvxRelief(L, g, n2, 0.35f, 0.65f, 3.0f),
                0.35f + 0.65f * (glm::dot(L, g) + 3.0f * glm::clamp(glm::dot(Lstar, g), 0.0f, 1.0f)), 1e-6f);
}

TEST(Enhancers, ContextProbeFollowsEquations617And618) {
    const glm::vec3 centre(0, 0, 0), axis(0, 0, 1), v(0, 0, -1);
    // A sample 10 mm in front of the centre plane (towards the viewer), radius 20.
    auto x = sample({0, 0, 10}, v, glm::vec3(1, 0, 0.5f), 0.6f, 0.5f);
    hvxContextProbe(x, centre, 20, axis, 0.015f, 0.95f, 0.8f, 1.0f);
    const float omegaD = 1 - 0.25f;  // along = -10: 1 - (10/20)^2
    const float facing = 0.5f / std::sqrt(1.25f);
    const float eta = 1.0f * hvxSmooth(0.015f, 0.95f, 0.6f) * std::pow(1 - facing, 4.0f);
    EXPECT_NEAR(x.a, 0.5f * eta * omegaD, 1e-6f);                  // lerp(0, eta, omega_d)
    EXPECT_NEAR(x.c.r, 0.8f * (1 - eta), 1e-6f);                    // 1 - eta
    // 10 mm behind the plane: lerp(eta, 1, 1 - omega_d) for both factors.
    x = sample({0, 0, -10}, v, glm::vec3(1, 0, 0.5f), 0.6f, 0.5f);
    hvxContextProbe(x, centre, 20, axis, 0.015f, 0.95f, 0.8f, 1.0f);
    EXPECT_NEAR(x.a, 0.5f * (eta + (1 - eta) * (1 - omegaD)), 1e-6f);
    // Outside the sphere: untouched.
    x = sample({0, 0, 30}, v, glm::vec3(1, 0, 0.5f), 0.6f, 0.5f);
    hvxContextProbe(x, centre, 20, axis, 0.015f, 0.95f, 0.8f, 1.0f);
    EXPECT_FLOAT_EQ(x.a, 0.5f);
}

TEST(Enhancers, BandPickerAndMimdaAccumulation) {
    const glm::vec4 band(100, 200, 300, 400);
    EXPECT_FLOAT_EQ(hvxBand(band, 150), 0.5f);
    EXPECT_FLOAT_EQ(hvxBand(band, 250), 1.0f);
    EXPECT_FLOAT_EQ(hvxBand(band, 450), 0.0f);
    auto x = sample({0, 0, 0}, {0, 0, -1}, {1, 0, 0}, 0.5f, 0.4f);
    x.s = 50;  // outside the band, looking straight along the axis: gone
    hvxBandPicker(x, band, {0, 0, 1}, 0.5f, 1.0f);
    EXPECT_FLOAT_EQ(x.a, 0.0f);
    EXPECT_FLOAT_EQ(x.importance, 0.0f);
    x = sample({0, 0, 0}, {1, 0, 0}, {1, 0, 0}, 0.5f, 0.4f);
    x.s = 50;  // at right angles to the axis: context stays
    hvxBandPicker(x, band, {0, 0, 1}, 0.5f, 1.0f);
    EXPECT_FLOAT_EQ(x.a, 0.4f);
    // MImDA (Eqs 3.2-3.3) with gamma = 0 is front-to-back compositing.
    glm::vec4 accum(0.2f, 0.1f, 0.0f, 0.3f);
    float imax = 0.5f;
    hvxMimda(accum, imax, {0.4f, 0.4f, 0.4f}, 0.5f, 0.9f, 0.0f);
    EXPECT_NEAR(accum.r, 0.2f + 0.7f * 0.4f, 1e-6f);
    EXPECT_NEAR(accum.a, 0.3f + 0.7f * 0.5f, 1e-6f);
    // gamma = 1 and an importance rise of 0.4: beta = 0.6 weighs down what lies in front.
    accum = glm::vec4(0.2f, 0.1f, 0.0f, 0.3f);
    imax = 0.5f;
    hvxMimda(accum, imax, {0.4f, 0.4f, 0.4f}, 0.5f, 0.9f, 1.0f);
    EXPECT_NEAR(accum.r, 0.2f * 0.6f + (1 - 0.6f * 0.3f) * 0.4f, 1e-6f);
    EXPECT_NEAR(accum.a, 0.3f * 0.6f + (1 - 0.6f * 0.3f) * 0.5f, 1e-6f);
    EXPECT_FLOAT_EQ(imax, 0.9f);
    EXPECT_NEAR(hvxMimdaFutureDelta(0.995f, 0.2f, 0.0f), 0.005f, 1e-6f) << "gamma 0: the usual opacity test";
    EXPECT_GT(hvxMimdaFutureDelta(0.995f, 0.2f, 1.0f), 0.5f) << "important content may still come";
}

TEST(ToolSet, OutOfRangeParametersAreRefusedAndJsonRoundTrips) {
    core::ToolSet t;
    t.clip.enabled = true;
    t.focal.enabled = true;
    t.focal.p = 4;
    t.focal.centre = {1, 2, 3};
    t.focal.rotationDegrees = {0, 0, 90};
    t.mimda.enabled = true;
    t.mimda.gamma = 0.25;
    t.band.band = {-100, 0, 200, 300};
    t.focal.contextStep = 6;
    EXPECT_NO_THROW(t.validate());
    const auto back = core::ToolSet::fromJson(t.toJson());
    EXPECT_DOUBLE_EQ(back.focal.contextStep, 6);
    EXPECT_DOUBLE_EQ(core::ToolSet::fromJson("{}").focal.contextStep, 3) << "the default";
    EXPECT_EQ(back.variantBits(), t.variantBits());
    EXPECT_EQ(back.focal.centre, t.focal.centre);
    EXPECT_DOUBLE_EQ(back.focal.p, 4);
    EXPECT_EQ(back.focal.rotationDegrees, t.focal.rotationDegrees);
    // 90 degrees about z: the probe's x axis points along the patient's y.
    EXPECT_NEAR(glm::length(t.focal.rotation()[0] - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(back.mimda.gamma, 0.25);
    EXPECT_EQ(back.band.band, t.band.band);
    auto bad = t;
    bad.mimda.gamma = 1.5;
    EXPECT_THROW(bad.validate(), core::Error);
    bad = t;
    bad.focal.rho = 1.0;
    EXPECT_THROW(bad.validate(), core::Error);
    bad = t;
    bad.band.band = {300, 200, 100, 0};
    EXPECT_THROW(bad.validate(), core::Error);
    bad = t;
    bad.clip.normal = {0, 0, 0};
    EXPECT_THROW(bad.validate(), core::Error);
    bad = t;
    bad.focal.radii = {10, -1, 10};
    EXPECT_THROW(bad.validate(), core::Error);
    for (const double step : {0.0, 2.5, 9.0, std::nan("")}) {  // a whole number of samples, 1 to 8
        bad = t;
        bad.focal.contextStep = step;
        EXPECT_THROW(bad.validate(), core::Error) << step;
    }
    EXPECT_THROW(core::ToolSet::fromJson("{\"focal\": {\"contextStep\": 1.5}}"), core::Error);
    EXPECT_THROW(core::ToolSet::fromJson("{\"mimda\": {\"gamma\": 7}}"), core::Error);
    EXPECT_THROW(core::ToolSet::fromJson("{\"clip\": {\"normal\": [1, 2]}}"), core::Error);
    EXPECT_THROW(core::ToolSet::fromJson("not json"), core::Error);
}

TEST(Enhancers, WhatTheToolsHideIsFullyTransparentWhateverTheSample) {
    // hvxHidden lets the ray caster skip a sample's gradient and enhancers, and hvxVisibleSpan
    // the samples outside it; each sample they declare hidden must come out of the whole chain with opacity exactly 0, whatever its
    // value, colour, opacity and gradient. Random tools, rays and samples; the chain is run on
    // each hidden one.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), pos(0.0f, 1.0f);
    auto unit = [&] {
        glm::vec3 v;
        do v = {u(rng), u(rng), u(rng)};
        while (glm::length(v) < 0.1f);
        return glm::normalize(v);
    };
    using T = core::ToolSet;
    int hidden = 0, checked = 0, outsideSpan = 0, inGap = 0;
    for (int bits : {int(T::FocalBit), int(T::ClipBit), int(T::ContextBit), T::ClipBit | T::ContextBit,
                     T::ClipBit | T::FocalBit | T::BandBit, T::ClipBit | T::ContextBit | T::FocalBit,
                     T::FocalBit | T::BandBit | T::MimdaBit}) {
        const int hiddenBefore = hidden, outsideBefore = outsideSpan, inGapBefore = inGap;
        for (int trial = 0; trial < 40; ++trial) {
            core::ToolSet t;
            t.clip.enabled = bits & T::ClipBit;
            t.clip.normal = glm::dvec3(unit());
            t.clip.offset = 20.0 * u(rng);
            t.focal.enabled = bits & T::FocalBit;
            t.focal.centre = glm::dvec3(10.0f * unit());
            t.focal.radii = {20 + 20 * pos(rng), 20 + 20 * pos(rng), 20 + 20 * pos(rng)};
            t.focal.p = trial % 3 == 0 ? 2 : 4;
            t.focal.q = trial % 2 == 0 ? 2 : 6;
            t.focal.rotationDegrees = {90.0 * u(rng), 90.0 * u(rng), 90.0 * u(rng)};
            t.context.enabled = bits & T::ContextBit;
            t.context.centre = glm::dvec3(10.0f * unit());
            t.context.radius = 30 + 20 * pos(rng);
            t.context.axis = glm::dvec3(unit());
            t.band.enabled = bits & T::BandBit;
            t.band.band = {50, 80, 150, 200};
            t.mimda.enabled = bits & T::MimdaBit;
            // every other trial far from the patient origin, as a scanner's table positions are
            const glm::vec3 shift = trial % 2 ? glm::vec3(1500, -900, 1800) : glm::vec3(0.0f);
            t.clip.offset -= glm::dot(t.clip.normal, glm::dvec3(shift));
            t.focal.centre += glm::dvec3(shift);
            t.context.centre += glm::dvec3(shift);
            const auto tools = core::packTools(t, {0.3, 0.7, 0.2, 16});
            const glm::vec3 eye = shift + 300.0f * unit();
            for (int ray = 0; ray < 50; ++ray) {
                const glm::vec3 v = glm::normalize(shift - eye + 40.0f * unit());
                const float hTheta = (bits & T::FocalBit) ? hvxFocalAngle(tools, eye, v) : 1.0f;
                // the ray caster starts and ends a ray at hvxVisibleSpan: all outside it is hidden
                const glm::vec2 span = hvxVisibleSpan(tools, bits, eye, v, hTheta);
                // and jumps over hvxHiddenGap: all inside it is hidden too
                const glm::vec2 gap = hvxHiddenGap(tools, bits, eye, v);
                // random samples, and each end of the span and the gap and a float step either side
                std::vector<float> alongs;
                for (int k = 0; k < 60; ++k) alongs.push_back(200.0f + 200.0f * pos(rng));
                for (float end : {span.x, span.y, gap.x, gap.y})
                    if (end > 0.0f && end < 1000.0f)
                        for (float a : {std::nextafter(end, 0.0f), end, std::nextafter(end, 1e4f)}) alongs.push_back(a);
                for (const float along : alongs) {
                    const glm::vec3 p = eye + v * along;
                    if (along < span.x || along > span.y) {
                        EXPECT_TRUE(hvxHidden(tools, bits, p, v, hTheta)) << "tools " << bits << " outside the span";
                        ++outsideSpan;
                    }
                    if (along >= gap.x && along <= gap.y) {
                        EXPECT_TRUE(hvxHidden(tools, bits, p, v, hTheta)) << "tools " << bits << " in the gap";
                        ++inGap;
                    }
                    if (!hvxHidden(tools, bits, p, v, hTheta)) continue;
                    ++hidden;
                    for (int s = 0; s < 4; ++s) {
                        auto x = sample(p, v, 50.0f * unit(), pos(rng), pos(rng));
                        x.s = 250 * pos(rng);
                        x.importance = pos(rng);
                        const float norm = (bits & T::FocalBit) ? hvxFocalNorm(tools, p) : 2.0f;
                        bool entered = false;
                        hvxEnhance(x, tools, bits, norm, 50.0f * unit(), hTheta, entered);
                        EXPECT_EQ(x.a, 0.0f) << "tools " << bits << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
                        EXPECT_FALSE(entered) << "a hidden sample opened the focal probe";
                        ++checked;
                    }
                }
            }
        }
        if (bits & T::MimdaBit) EXPECT_EQ(hidden, hiddenBefore) << "nothing is hidden under MImDA";
        else EXPECT_GT(hidden, hiddenBefore + 100) << "tools " << bits << " hide something";
        // the focus cone's ends, and the cut-away side of a clip plane seen face-on, are skipped
        if (bits == T::FocalBit || bits == T::ClipBit)
            EXPECT_GT(outsideSpan, outsideBefore + 100) << "tools " << bits << " skip part of the ray";
        // the context probe's front half, seen across its axis, is jumped over
        if (bits == T::ContextBit) EXPECT_GT(inGap, inGapBefore + 100) << "tools " << bits << " skip part of the ray";
        if (bits & (T::FocalBit | T::MimdaBit)) EXPECT_EQ(inGap, inGapBefore) << "tools " << bits << ": no gap";
    }
    std::printf("%d hidden samples, %d runs of the chain, %d samples outside the visible span, %d in a hidden gap\n",
                hidden, checked, outsideSpan, inGap);
    EXPECT_GT(hidden, 2000);
    EXPECT_GT(outsideSpan, 500) << "focus cones and face-on clip planes that skip part of the ray";
}

TEST(ToolSet, TheFocalProbesBoundingSphereHoldsTheWholeProbe) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double p : {0.5, 1.0, 2.0, 4.0, 16.0, 64.0})
        for (double q : {0.5, 2.0, 3.0, 8.0, 64.0}) {
            core::ToolSet t;
            t.focal.radii = {30, 45, 20};
            t.focal.p = p;
            t.focal.q = q;
            t.focal.rotationDegrees = {20, -35, 70};
            const auto tools = core::packTools(t, {0.3, 0.7, 0.2, 16});
            const double bound = t.focal.boundingRadius();
            EXPECT_LE(bound, glm::length(t.focal.radii) + 1e-9);
            double farthest = 0;
            for (int i = 0; i < 20000; ++i) {  // points of the box, kept where inside the probe
                const glm::dvec3 local(u(rng), u(rng), u(rng));
                const glm::dvec3 w = t.focal.rotation() * (local * t.focal.radii);
                if (hvxFocalNorm(tools, glm::vec3(w)) <= 1.0f) farthest = std::max(farthest, glm::length(w));
            }
            EXPECT_LE(farthest, bound * (1 + 1e-5)) << "p " << p << " q " << q;
            if (p == 2 && q == 2) EXPECT_DOUBLE_EQ(bound, 45.0) << "a sphere's bound is its largest radius";
        }
}

// Focus and context sampling: a ray steps k samples at a time before and behind the focal
// probe's chord and one at a time within it, always a whole number of samples (on its grid),
// and never steps past the chord's first sample.
TEST(Enhancers, TheContextStepLandsOnTheRaysGridJustBeforeTheFocus) {
    using core::glsl::hvxStepAfter;
    const glm::vec2 chord(10.0f, 20.0f);
    const float dt = 0.5f;
    EXPECT_FLOAT_EQ(hvxStepAfter(0.0f, dt, chord, 4.0f), 2.0f);   // far before: k·dt
    EXPECT_FLOAT_EQ(hvxStepAfter(8.5f, dt, chord, 4.0f), 1.5f);   // three samples to 10: land on it
    EXPECT_FLOAT_EQ(hvxStepAfter(9.75f, dt, chord, 4.0f), 0.5f);  // less than a sample away: one
    EXPECT_FLOAT_EQ(hvxStepAfter(15.0f, dt, chord, 4.0f), 0.5f);  // in the focus: every sample
    EXPECT_FLOAT_EQ(hvxStepAfter(20.0f, dt, chord, 4.0f), 2.0f);  // behind it: k·dt
    EXPECT_FLOAT_EQ(hvxStepAfter(3.0f, dt, glm::vec2(1e30f, -1e30f), 4.0f), 2.0f);  // a ray that misses it
    EXPECT_FLOAT_EQ(hvxStepAfter(3.0f, dt, glm::vec2(-1e30f, 1e30f), 4.0f), 0.5f);  // no probe: every sample
    for (float t = 0.0f; t < 30.0f;) {  // a march never jumps over the chord's start
        const float next = t + hvxStepAfter(t, dt, chord, 4.0f);
        EXPECT_FALSE(t < chord.x && next > chord.x) << t << " -> " << next;
        t = next;
    }
    core::ToolSet tools;
    tools.focal.enabled = true;
    tools.focal.radii = glm::dvec3(10);
    const auto packed = core::packTools(tools, glm::dvec4(0.3, 0.7, 0.2, 20));
    const glm::vec2 through = core::glsl::hvxFocusChord(packed, core::ToolSet::FocalBit, glm::vec3(0, 0, -50), glm::vec3(0, 0, 1));
    EXPECT_NEAR(through.x, 40.0f, 0.02f);
    EXPECT_NEAR(through.y, 60.0f, 0.02f);
    tools.focal.contextStep = 1;  // the dense march: no chord, every sample
    const glm::vec2 none = core::glsl::hvxFocusChord(core::packTools(tools, glm::dvec4(0.3, 0.7, 0.2, 20)),
                                                     core::ToolSet::FocalBit, glm::vec3(0, 0, -50), glm::vec3(0, 0, 1));
    EXPECT_LT(none.x, -1e29f);
    EXPECT_GT(none.y, 1e29f);
}
