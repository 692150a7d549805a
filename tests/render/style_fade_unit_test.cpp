// SPDX-License-Identifier: Apache-2.0
// The day/night cross-fade as values: the mixed style at both ends is the style itself, every
// colour moves between them, and the fade's weight follows the clock (docs/rendering.md "Day and night").
#include <gtest/gtest.h>

#include "navmap/render/style_fade.h"

namespace {

using namespace navmap::render;

bool sameColours(const MapStyle& a, const MapStyle& b) {
    for (std::size_t i = 0; i < a.roads.classes.size(); ++i) {
        if (a.roads.classes[i].fill != b.roads.classes[i].fill ||
            a.roads.classes[i].casing != b.roads.classes[i].casing)
            return false;
    }
    return a.sky_color == b.sky_color && a.brightness == b.brightness && a.far_ground_color == b.far_ground_color &&
           a.roads.outline == b.roads.outline && a.route_color == b.route_color && a.route_casing == b.route_casing &&
           a.glow_color == b.glow_color && a.marker_color == b.marker_color &&
           a.street_bar_panel == b.street_bar_panel && a.street_bar_text == b.street_bar_text;
}

TEST(StyleFade, EndsAreTheStylesBitForBit) {
    const MapStyle day = MapStyle::day(), night = MapStyle::night();
    EXPECT_TRUE(sameColours(mixStyles(day, night, 0.0f), day));
    EXPECT_TRUE(sameColours(mixStyles(day, night, 1.0f), night));
    EXPECT_TRUE(sameColours(mixStyles(day, night, -3.0f), day));
    EXPECT_TRUE(sameColours(mixStyles(day, night, 7.0f), night));
    EXPECT_FALSE(sameColours(day, night));
}

TEST(StyleFade, EveryColourMovesHalfwayAtOneHalf) {
    const MapStyle day = MapStyle::day(), night = MapStyle::night();
    const MapStyle mid = mixStyles(day, night, 0.5f);
    EXPECT_FLOAT_EQ(mid.brightness, 0.5f * (day.brightness + night.brightness));
    EXPECT_FLOAT_EQ(mid.sky_color.b, 0.5f * (day.sky_color.b + night.sky_color.b));
    EXPECT_FLOAT_EQ(mid.route_color.r, 0.5f * (day.route_color.r + night.route_color.r));
    EXPECT_FLOAT_EQ(mid.glow_color.r, 0.5f * (day.glow_color.r + night.glow_color.r));
    EXPECT_FLOAT_EQ(mid.roads.outline.g, 0.5f * (day.roads.outline.g + night.roads.outline.g));
    EXPECT_FLOAT_EQ(mid.street_bar_panel.a, 0.5f * (day.street_bar_panel.a + night.street_bar_panel.a));
    EXPECT_FLOAT_EQ(mid.street_bar_text.r, 0.5f * (day.street_bar_text.r + night.street_bar_text.r));
    EXPECT_NE(day.street_bar_text.r, night.street_bar_text.r) << "the bar's text dims at night";
    for (std::size_t i = 0; i < day.roads.classes.size(); ++i) {
        EXPECT_FLOAT_EQ(mid.roads.classes[i].fill.r,
                        0.5f * (day.roads.classes[i].fill.r + night.roads.classes[i].fill.r));
        EXPECT_FLOAT_EQ(mid.roads.classes[i].casing.g,
                        0.5f * (day.roads.classes[i].casing.g + night.roads.classes[i].casing.g));
    }
}

TEST(StyleFade, WeightFollowsTheClockOverTwoSeconds) {
    StyleFade fade;
    fade.reset(false);
    EXPECT_EQ(fade.weightAt(100.0), 0.0f);
    fade.target(true, 100.0);
    EXPECT_TRUE(fade.night());
    EXPECT_FLOAT_EQ(fade.weightAt(100.5), 0.25f);
    EXPECT_FLOAT_EQ(fade.weightAt(101.0), 0.5f);
    EXPECT_TRUE(fade.fading(101.9));
    EXPECT_EQ(fade.weightAt(102.0), 1.0f);
    EXPECT_FALSE(fade.fading(102.0));
    fade.target(true, 103.0);  // the same target: nothing starts
    EXPECT_EQ(fade.weightAt(103.0), 1.0f);
}

TEST(StyleFade, ReversedMidwayTurnsBackFromWhereItStands) {
    StyleFade fade;
    fade.reset(false);
    fade.target(true, 0.0);
    fade.target(false, 1.5);  // at 0.75
    EXPECT_FLOAT_EQ(fade.weightAt(1.5), 0.75f);
    EXPECT_FLOAT_EQ(fade.weightAt(2.5), 0.25f);
    EXPECT_EQ(fade.weightAt(3.0), 0.0f);
    fade.reset(true);
    EXPECT_EQ(fade.weightAt(0.0), 1.0f);
}

}  // namespace
