// The 3D view's camera and the transfer-function curves the editor works on.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "core/base/Error.h"
#include "core/camera/OrbitCamera.h"
#include "core/appearance/TransferFunctionSpec.h"

using namespace hvx;

TEST(OrbitCamera, StandardViewsFollowRadiologicalConventions) {
    core::OrbitCamera cam;
    cam.frame({10, 20, 30}, 100);
    using S = core::OrbitCamera::Standard;
    struct Expect {
        S view;
        const char *right, *up, *towardsEye;
    };
    for (const auto& e : {Expect{S::Anterior, "L", "S", "A"}, Expect{S::Posterior, "R", "S", "P"},
                          Expect{S::Left, "P", "S", "L"}, Expect{S::Right, "A", "S", "R"},
                          Expect{S::Superior, "R", "A", "S"}, Expect{S::Inferior, "L", "A", "I"}}) {
        cam.setStandard(e.view);
        EXPECT_EQ(core::OrbitCamera::patientLabel(cam.right()), e.right) << int(e.view);
        EXPECT_EQ(core::OrbitCamera::patientLabel(cam.up()), e.up) << int(e.view);
        EXPECT_EQ(core::OrbitCamera::patientLabel(cam.back()), e.towardsEye) << int(e.view);
        EXPECT_NEAR(glm::length(glm::cross(cam.right(), cam.up()) - cam.back()), 0.0, 1e-12) << "right-handed";
    }
}

TEST(OrbitCamera, AnteriorViewMatchesTheOrbitViewOfTheRayCasterTests) {
    core::OrbitCamera cam;
    cam.frame({0, 0, 0}, 100);
    cam.setStandard(core::OrbitCamera::Standard::Anterior);
    const auto v = cam.view(64, 48);
    const auto o = core::View::orbit({0, 0, 0}, cam.distance(), 0, 0, 64, 48);
    EXPECT_NEAR(glm::length(v.eye - o.eye), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(v.up - o.up), 0.0, 1e-9);
}

TEST(OrbitCamera, TrackballPanAndZoom) {
    core::OrbitCamera cam;
    cam.frame({0, 0, 0}, 100);
    cam.setStandard(core::OrbitCamera::Standard::Anterior);
    cam.rotate(250, 0, 500);  // half the height: 90 degrees about the up axis
    EXPECT_EQ(core::OrbitCamera::patientLabel(cam.back()), "R") << "dragging right brings the patient's right side round";
    cam.rotate(-250, 0, 500);
    EXPECT_EQ(core::OrbitCamera::patientLabel(cam.back()), "A");
    cam.rotate(0, 125, 500);  // 45 degrees about the right axis: an oblique label
    EXPECT_EQ(core::OrbitCamera::patientLabel(cam.back()), "AS");
    const double d = cam.distance();
    cam.zoom(2.0);
    EXPECT_NEAR(cam.distance(), d / 2, 1e-9);
    cam.zoom(1e-9);  // clamped, never absurd
    EXPECT_LE(cam.distance(), 100 * 50.0);
    const auto before = cam.target();
    cam.pan(10, 0, 500);
    EXPECT_LT(glm::dot(cam.target() - before, cam.right()), 0.0) << "the scene follows the pointer";
    EXPECT_EQ(core::OrbitCamera::patientLabel({0.7, -0.7, 0.1}), "LA");
}

TEST(TransferFunctionSpec, CurvesMergeIntoATransferFunctionAndWindowLevelMovesThem) {
    const auto preset = core::TransferFunction::preset("ct-bone", -1024, 3071, 1, 0, 1);
    auto spec = core::TransferFunctionSpec::from(preset);
    ASSERT_EQ(spec.opacity.size(), preset.points().size());
    EXPECT_DOUBLE_EQ(spec.opacityAt(300), 0.35);
    EXPECT_DOUBLE_EQ(spec.opacityAt(900), 0.35 + (0.9 - 0.35) * 0.5);
    spec.colours = {{0, {1, 0, 0}}, {1000, {0, 0, 1}}};  // colour stops apart from opacity points
    const auto tf = spec.build(-1024, 3071, 1);
    EXPECT_NEAR(tf.sample(500).r / tf.sample(500).a, 0.5, 0.01);
    EXPECT_NEAR(1.0 - std::exp(-tf.sample(500).a), spec.opacityAt(500), 0.01);  // extinction per reference length
    // Level +100, window x2 about 300: the 300 HU point moves to 400, 1500 to 2800.
    const auto w = spec.windowed(300, 100, 2.0);
    EXPECT_DOUBLE_EQ(w.opacity[2].value, 400);
    EXPECT_DOUBLE_EQ(w.opacity[3].value, 2800);
    EXPECT_THROW(spec.windowed(300, 0, 0), core::Error);
    auto bad = spec;
    bad.opacity[1].alpha = 1.5;
    EXPECT_THROW(bad.build(0, 1, 1), core::Error);
    bad = spec;
    bad.colours.clear();
    EXPECT_THROW(bad.build(0, 1, 1), core::Error);
}
