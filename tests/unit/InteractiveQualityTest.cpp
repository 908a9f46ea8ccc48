// Interaction quality: reduced resolution and a doubled step while moving, sized to the target
// frame time from measured frames; full quality as soon as the camera stops.
#include <gtest/gtest.h>

#include "core/camera/InteractiveQuality.h"
#include "core/camera/View.h"

using namespace hvx;

TEST(InteractiveQuality, StillFramesAreFullQualityAtOnce) {
    core::InteractiveQuality q;
    EXPECT_TRUE(q.next(false).full());
    q.frameDone(q.next(true), 500.0);
    EXPECT_FALSE(q.next(true).full());
    EXPECT_TRUE(q.next(false).full()) << "the first frame after the camera stops is full quality";
}

TEST(InteractiveQuality, MovingFramesAreSizedToTheTargetFrameTime) {
    core::InteractiveQuality q({40.0, 0.25, 2.0});
    const auto first = q.next(true);
    EXPECT_EQ(first.stepScale, 2.0);
    EXPECT_EQ(first.resolution, 0.5);  // nothing measured yet
    // A full frame costs 320 ms: work must shrink 8×, the step gives 2×, so 4× fewer pixels.
    q.frameDone({}, 320.0);
    EXPECT_DOUBLE_EQ(q.fullFrameMs(), 320.0);
    EXPECT_NEAR(q.next(true).resolution, 0.5, 1e-12);
    // A fast volume needs no reduction of pixels, only of the step.
    core::InteractiveQuality fast({40.0, 0.25, 2.0});
    fast.frameDone({}, 20.0);
    EXPECT_EQ(fast.next(true).resolution, 1.0);
    // A very slow one stops at the minimum resolution.
    core::InteractiveQuality slow({40.0, 0.25, 2.0});
    slow.frameDone({}, 100000.0);
    EXPECT_EQ(slow.next(true).resolution, 0.25);
}

TEST(InteractiveQuality, MeasurementsOfReducedFramesAreScaledToAFullFrameAndSmoothed) {
    core::InteractiveQuality q;
    q.frameDone({0.5, 2.0}, 10.0);  // 1/8 of the work in 10 ms: a full frame is 80 ms
    EXPECT_DOUBLE_EQ(q.fullFrameMs(), 80.0);
    q.frameDone({}, 180.0);  // one slow frame moves the estimate by 30%
    EXPECT_DOUBLE_EQ(q.fullFrameMs(), 0.7 * 80.0 + 0.3 * 180.0);
    q.frameDone({}, 0.0);  // no timing: ignored
    EXPECT_DOUBLE_EQ(q.fullFrameMs(), 0.7 * 80.0 + 0.3 * 180.0);
}

TEST(InteractiveQuality, SubFramesDrawAQuarterOfThePixelsSoTheResolutionCanBeHigher) {
    core::InteractiveQuality q({40.0, 0.25, 2.0, true});
    EXPECT_TRUE(q.next(true).subFrame);
    EXPECT_FALSE(q.next(true).full());
    EXPECT_TRUE(q.next(false).full()) << "still frames are whole frames";
    EXPECT_FALSE(q.next(false).subFrame);
    // A sub-frame at half resolution and double step is 1/32 of the work: 10 ms means 320 ms a full frame.
    q.frameDone(q.next(true), 10.0);
    EXPECT_DOUBLE_EQ(q.fullFrameMs(), 10.0 / (0.25 / 2.0 * 0.25));
    // 40 ms a frame then allows 320 / 2 / 4 = 40: the whole resolution (plain frames: half).
    EXPECT_DOUBLE_EQ(q.next(true).resolution, 1.0);
    core::InteractiveQuality plain({40.0, 0.25, 2.0, false});
    plain.frameDone({}, 320.0);
    EXPECT_NEAR(plain.next(true).resolution, 0.5, 1e-12);
}

TEST(View, ScaledKeepsTheCameraAndScalesThePixelCount) {
    auto v = core::View::orbit({0, 0, 0}, 500.0, 30.0, 10.0, 640, 480);
    const auto half = v.scaled(0.5);
    EXPECT_EQ(half.width, 320);
    EXPECT_EQ(half.height, 240);
    EXPECT_EQ(half.eye, v.eye);
    EXPECT_EQ(half.fovYDegrees, v.fovYDegrees);
    EXPECT_EQ(v.scaled(1e-6).width, 1);
}
