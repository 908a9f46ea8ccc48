#include <gtest/gtest.h>

#include <random>

#include "core/appearance/TransferFunction.h"

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
