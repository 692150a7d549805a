// SPDX-License-Identifier: Apache-2.0
// The distance countdown: each step at its boundary, kilometres above 1 km, "now" below 20 m.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "navmap/map/guidance/countdown.h"

namespace navmap::map::guidance {
namespace {

TEST(GuidanceCountdown, StepsAtTheirBoundaries) {
    struct Case {
        double d;
        const char* text;
    };
    for (const Case& c : std::vector<Case>{
             {-5.0, "now"},      {0.0, "now"},       {19.99, "now"},     {20.0, "50 m"},     {49.9, "50 m"},
             {50.0, "50 m"},     {99.99, "50 m"},    {100.0, "100 m"},   {199.9, "100 m"},   {200.0, "200 m"},
             {299.9, "200 m"},   {300.0, "300 m"},   {499.9, "300 m"},   {500.0, "500 m"},   {799.9, "500 m"},
             {800.0, "800 m"},   {999.9, "800 m"},   {1000.0, "1.0 km"}, {1099.9, "1.0 km"}, {1200.0, "1.2 km"},
             {1299.9, "1.2 km"}, {9999.9, "9.9 km"}, {10000.0, "10 km"}, {12345.0, "12 km"}}) {
        EXPECT_EQ(formatCountdown(c.d), c.text) << c.d;
    }
}

TEST(GuidanceCountdown, KindsAndValues) {
    EXPECT_EQ(countdownFor(10.0), (Countdown{Countdown::Kind::Now, 0.0}));
    EXPECT_EQ(countdownFor(350.0), (Countdown{Countdown::Kind::Metres, 300.0}));
    EXPECT_EQ(countdownFor(25000.0), (Countdown{Countdown::Kind::Kilometres, 25.0}));
    EXPECT_EQ(countdownFor(std::nan("")).kind, Countdown::Kind::Invalid);
    EXPECT_EQ(countdownFor(std::numeric_limits<double>::infinity()).kind, Countdown::Kind::Invalid);
    EXPECT_EQ(formatCountdown(std::nan("")), "");
}

TEST(GuidanceCountdown, NeverAnnouncesMoreThanIsLeftAndNeverGoesUpWhileApproaching) {
    double previous = std::numeric_limits<double>::infinity();
    for (double d = 3000.0; d >= 0.0; d -= 0.5) {
        const Countdown c = countdownFor(d);
        const double shown = c.kind == Countdown::Kind::Kilometres ? c.value * 1000.0
                             : c.kind == Countdown::Kind::Metres   ? c.value
                                                                   : 0.0;
        // Only the last step (50 m, held until "now") may exceed the distance left.
        if (d >= 50.0) {
            EXPECT_LE(shown, d + 1e-9) << d;
        }
        EXPECT_LE(shown, previous + 1e-9) << d;
        previous = shown;
    }
}

}  // namespace
}  // namespace navmap::map::guidance
