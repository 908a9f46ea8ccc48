#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/appearance/TransferFunction.h"
#include "core/base/Error.h"

using namespace hvx;

TEST(TransferFunction, SegmentExtinctionIsTheSegmentsOpacityComponentExactly) {
    // The ray casters test a segment's opacity first and take its colour only when it shows,
    // so the two must agree to the last bit, long segments (Eq. 3.1) and short ones alike.
    const auto tf = core::TransferFunction::preset("ct-soft-tissue", -1024.0, 3071.0, 1.0, 0.0, 1.0);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> value(-1100.0, 3100.0), small(-0.01, 0.01);
    for (int i = 0; i < 20000; ++i) {
        const double a = value(rng);
        const double b = i % 2 ? value(rng) : a + small(rng);
        EXPECT_EQ(tf.segmentExtinction(a, b), tf.segment(a, b).w) << a << " " << b;
    }
    EXPECT_EQ(tf.segmentExtinction(-1024.0, -1000.0), 0.0);  // air is transparent in this preset
    EXPECT_GT(tf.segmentExtinction(200.0, 400.0), 0.0);
}

// Every entry of every preset's table is its control points' piecewise-linear colour and
// opacity at that entry's value, turned into extinction as the header defines it (tau =
// -ln(1 - a) / d_ref, k = tau * colour): an entry moved, swapped or shifted by one fails here.
TEST(TransferFunction, EveryEntryIsTheControlPointsInterpolatedAtItsValue) {
    for (const auto& name : core::TransferFunction::presetNames()) {
        const double lo = -1024, hi = 3071, ref = 2.5;
        const auto tf = core::TransferFunction::preset(name, lo, hi, 1.0, 0.0, ref);
        auto points = tf.points();
        std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.value < b.value; });
        int wrong = 0;
        for (int i = 0; i < core::TransferFunction::kEntries; ++i) {
            const double v = lo + (hi - lo) * (i + 0.5) / core::TransferFunction::kEntries;
            glm::dvec4 c = points.front().rgba;
            for (std::size_t p = 1; p < points.size(); ++p)
                if (v >= points[p - 1].value && v <= points[p].value && points[p].value > points[p - 1].value) {
                    const double t = (v - points[p - 1].value) / (points[p].value - points[p - 1].value);
                    c = points[p - 1].rgba + (points[p].rgba - points[p - 1].rgba) * t;
                    break;
                }
            if (v > points.back().value) c = points.back().rgba;
            const double tau = -std::log(1.0 - std::clamp(c.a, 0.0, 0.999999)) / ref;
            const glm::dvec4 want(glm::dvec3(c) * tau, tau), got = tf.sample(v);
            for (int k = 0; k < 4; ++k)
                if (std::abs(got[k] - want[k]) > 1e-9 * (1.0 + std::abs(want[k])) && wrong++ < 3)
                    ADD_FAILURE() << name << " entry " << i << " (value " << v << ") component " << k << ": " << got[k]
                                  << ", the control points give " << want[k];
        }
        EXPECT_EQ(wrong, 0) << name;
    }
}

TEST(TransferFunction, RefractionIsPreIntegratedAndCountsAsContent) {
    // Transparent everywhere; ν rises from 1 at value 100 to 2 at value 300.
    core::TransferFunction tf({{0, glm::dvec4(0.0)}, {1000, glm::dvec4(0.0)}}, 0, 1000);
    EXPECT_TRUE(tf.isEmpty(0, 1000));
    EXPECT_EQ(tf.refractionSegment(200, 250), 1.0f) << "no curve: index 1";
    tf.setRefraction({{100, 1.0}, {300, 2.0}, {100, 1.0}});
    ASSERT_TRUE(tf.hasRefraction());
    // The segment's index is ν's average over the values it spans, worked by hand:
    // from 0 to 200 the curve is 1 up to 100, then 1 + (v − 100)/200: mean 1 + (100²/400)/200 = 1.125.
    EXPECT_NEAR(tf.refractionSegment(0, 200), 1.125f, 2e-3);
    EXPECT_NEAR(tf.refractionSegment(200, 0), 1.125f, 2e-3) << "either direction";
    EXPECT_NEAR(tf.refractionSegment(300, 900), 2.0f, 1e-4) << "constant beyond the last point";
    EXPECT_NEAR(tf.refractionSegment(200, 200.05f), 1.5f, 2e-3) << "within one entry: the midpoint's index";
    EXPECT_EQ(tf.refractionSegment(20, 60), 1.0f) << "air's entries are exactly 0 in the table";
    // Transparent but refracting values are not empty (the rays bend there); air still is.
    EXPECT_FALSE(tf.isEmpty(250, 260));
    EXPECT_TRUE(tf.isEmpty(0, 90));
    // A curve of 1 everywhere is no curve; an index outside [0.25, 4] is refused.
    tf.setRefraction({{0, 1.0}, {500, 1.0}});
    EXPECT_FALSE(tf.hasRefraction());
    EXPECT_TRUE(tf.isEmpty(0, 1000));
    EXPECT_THROW(tf.setRefraction({{0, 5.0}}), core::Error);
    EXPECT_THROW(tf.setRefraction({{std::nan(""), 1.5}}), core::Error);
}

TEST(TransferFunction, RefractionByOpacityFollowsTheOpacityCurve) {
    // Air refracts nothing; from 5 % opacity on, what shows refracts with the index given.
    const core::TransferFunction tf({{0, glm::dvec4(0.0)}, {100, glm::dvec4(1, 1, 1, 0.025)}, {200, glm::dvec4(1, 1, 1, 0.4)}}, 0, 300);
    const auto curve = tf.refractionByOpacity(1.5);
    ASSERT_EQ(curve.size(), 3u);
    EXPECT_DOUBLE_EQ(curve[0].index, 1.0);
    EXPECT_DOUBLE_EQ(curve[1].index, 1.25);
    EXPECT_DOUBLE_EQ(curve[2].index, 1.5);
    EXPECT_TRUE(tf.refractionByOpacity(1.0).empty());
    EXPECT_THROW(tf.refractionByOpacity(0.1), core::Error);
}

#include "core/appearance/ColorMap.h"

// An overlay stored with a negative rescale slope: its window's physical low end is the larger
// stored value, and the colour map runs down the stored values. Physical value p is stored as
// 10 - p here, so the map at stored 10 - p must be the plain map's at p (it had been swapped
// back into increasing order: physical 0 drew the top colour, opaque).
TEST(TransferFunction, ColourMapsFollowADecreasingRescale) {
    const auto hot = core::ColorMap::named("hot");
    const auto plain = core::TransferFunction::forColorMap(hot, 0.0, 10.0, 0.8, -10.0, 20.0, 1.0);
    const auto negated = core::TransferFunction::forColorMap(hot, 10.0, 0.0, 0.8, -10.0, 20.0, 1.0);
    for (double p = -10; p <= 20; p += 0.37) {
        const glm::dvec4 a = plain.sample(p), b = negated.sample(10.0 - p);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(a[c], b[c], 1e-9) << "physical " << p << ", channel " << c;
    }
    EXPECT_EQ(negated.sample(15.0).w, 0.0) << "physical -5: below the window, transparent";
    EXPECT_NEAR(negated.sample(-5.0).w, -std::log(1.0 - 0.8), 1e-9)
        << "physical 15: above it, the top colour at the opacity (0.8, as an extinction)";
    EXPECT_THROW(core::TransferFunction::forColorMap(hot, 3.0, 3.0, 0.5, 0.0, 10.0, 1.0), core::Error);
}
