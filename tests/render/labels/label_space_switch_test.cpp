// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

#include "labels/label_space_switch.h"

namespace nl = navmap::render::labels;

TEST(LabelSpaceSwitch, NeedsBothSteepAngleAndLowHeight) {
    // seed 5.5: WS only when (1) the angle is big enough AND (2) the camera is close enough.
    const nl::SpaceSwitchParams p;  // enter at tilt >= 60 and height <= 120
    EXPECT_EQ(nl::LabelSpaceSwitch::decide(nl::LabelSpace::Screen, 70, 80, p), nl::LabelSpace::World);
    EXPECT_EQ(nl::LabelSpaceSwitch::decide(nl::LabelSpace::Screen, 70, 400, p), nl::LabelSpace::Screen);
    EXPECT_EQ(nl::LabelSpaceSwitch::decide(nl::LabelSpace::Screen, 30, 80, p), nl::LabelSpace::Screen);
    EXPECT_EQ(nl::LabelSpaceSwitch::decide(nl::LabelSpace::Screen, 60, 120, p), nl::LabelSpace::World);
}

TEST(LabelSpaceSwitch, HysteresisPreventsFlicker) {
    nl::LabelSpaceSwitch sw;  // enter 60 deg / 120 m, exit 52 deg / 160 m
    EXPECT_EQ(sw.update(61, 100, 0.016), nl::LabelSpace::World);
    // Wobbling inside the band (52..60 deg, 120..160 m) keeps the decision.
    for (int i = 0; i < 100; ++i) {
        const float tilt = (i % 2 == 0) ? 59.0F : 53.0F;
        const float height = (i % 3 == 0) ? 150.0F : 110.0F;
        EXPECT_EQ(sw.update(tilt, height, 0.016), nl::LabelSpace::World) << i;
    }
    EXPECT_EQ(sw.update(51, 100, 0.016), nl::LabelSpace::Screen);  // below the exit angle
    for (int i = 0; i < 100; ++i) {
        EXPECT_EQ(sw.update((i % 2 == 0) ? 59.0F : 53.0F, 100, 0.016), nl::LabelSpace::Screen) << i;
    }
    EXPECT_EQ(sw.update(65, 100, 0.016), nl::LabelSpace::World);
    EXPECT_EQ(sw.update(65, 161, 0.016), nl::LabelSpace::Screen);  // climbed above the exit height
    // Non-finite input keeps the state.
    EXPECT_EQ(sw.update(NAN, 100, 0.016), nl::LabelSpace::Screen);
}

TEST(LabelSpaceSwitch, CrossFadesWithoutPop) {
    nl::SpaceSwitchParams p;
    p.crossfade_s = 0.5F;
    nl::LabelSpaceSwitch sw(p);
    EXPECT_EQ(sw.worldWeight(), 0.0F);
    sw.update(70, 50, 0.1);
    const float w1 = sw.worldWeight();
    EXPECT_GT(w1, 0.0F);
    EXPECT_LT(w1, 0.2F);  // smoothstep(0.2) = 0.104
    EXPECT_TRUE(sw.crossFading());
    float prev = w1;
    for (int i = 0; i < 3; ++i) {
        sw.update(70, 50, 0.1);
        EXPECT_GT(sw.worldWeight(), prev);
        EXPECT_LT(sw.worldWeight() - prev, 0.35F);  // no jump
        prev = sw.worldWeight();
    }
    sw.update(70, 50, 0.1);
    EXPECT_FLOAT_EQ(sw.worldWeight(), 1.0F);
    EXPECT_FALSE(sw.crossFading());
    // Switching back halfway reverses the fade from where it is.
    sw.update(40, 50, 0.2);
    EXPECT_EQ(sw.space(), nl::LabelSpace::Screen);
    EXPECT_NEAR(sw.worldWeight(), 0.648F, 1e-3F);  // smoothstep(0.6)
}

TEST(LabelSpaceSwitch, TiltFromLookDirection) {
    const glm::vec3 up{0, 0, 1};
    EXPECT_NEAR(nl::LabelSpaceSwitch::tiltDeg({0, 0, -1}, up), 0.0F, 1e-4F);
    EXPECT_NEAR(nl::LabelSpaceSwitch::tiltDeg({1, 0, 0}, up), 90.0F, 1e-4F);
    EXPECT_NEAR(nl::LabelSpaceSwitch::tiltDeg({0, 1, -1}, up), 45.0F, 1e-3F);
    EXPECT_EQ(nl::LabelSpaceSwitch::tiltDeg({0, 0, 0}, up), 0.0F);
}

TEST(LabelSpaceSwitch, RejectsThresholdsWithoutHysteresis) {
    nl::SpaceSwitchParams p;
    p.exit_tilt_deg = 65.0F;  // above enter_tilt_deg
    EXPECT_THROW(nl::LabelSpaceSwitch{p}, std::runtime_error);
    p = {};
    p.exit_height_m = 100.0F;  // below enter_height_m
    try {
        nl::LabelSpaceSwitch sw(p);
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("exit_height_m"), std::string::npos) << e.what();
    }
    nl::LabelSpaceSwitch world({}, nl::LabelSpace::World);
    EXPECT_EQ(world.worldWeight(), 1.0F);
}
