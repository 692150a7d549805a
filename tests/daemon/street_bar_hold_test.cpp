// SPDX-License-Identifier: Apache-2.0
// Which street the cluster's street bar shows (daemon/street_bar_hold.h): a street only after the
// match has held it 2 s of pose time, no change while the match flickers between two streets, the
// last street kept 2 s after the match is lost and then hidden.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "street_bar_hold.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

const render::StreetBar kMeritxell{"Avinguda Meritxell", "CG-1"};
const render::StreetBar kCarlemany{"Avinguda Carlemany", ""};
constexpr double kT0 = 1618394400.0;  // pose times are seconds since the epoch of the CAN clock
constexpr double kFrame = 1.0 / 30.0;

// Frames at 30 fps from `from_s` (relative to kT0) while t < `to_s`, all with `matched`; the
// street shown after the last one.
std::optional<render::StreetBar> frames(StreetBarHold& hold, double from_s, double to_s,
                                        const std::optional<render::StreetBar>& matched) {
    for (int i = 0; from_s + i * kFrame < to_s; ++i) hold.update(kT0 + from_s + i * kFrame, matched);
    return hold.shown();
}

}  // namespace

TEST(StreetBarHold, AStreetShowsOnlyAfterTheMatchHeldItForTwoSeconds) {
    StreetBarHold hold;
    EXPECT_FALSE(hold.shown());
    EXPECT_FALSE(frames(hold, 0.0, 1.99, kMeritxell)) << "not before 2 s";
    EXPECT_FALSE(hold.update(kT0 + 1.999, kMeritxell));
    const auto shown = hold.update(kT0 + 2.0, kMeritxell);
    ASSERT_TRUE(shown) << "at 2 s of the same street";
    EXPECT_EQ(*shown, kMeritxell);
    // Another street: the old one stays for 2 s, then the new one.
    EXPECT_EQ(frames(hold, 2.1, 4.05, kCarlemany), kMeritxell);
    EXPECT_EQ(hold.update(kT0 + 4.1, kCarlemany), kCarlemany);
    EXPECT_EQ(frames(hold, 4.2, 30.0, kCarlemany), kCarlemany) << "and stays";
}

TEST(StreetBarHold, FlickerBetweenTwoStreetsChangesNothing) {
    StreetBarHold hold;
    ASSERT_EQ(frames(hold, 0.0, 2.5, kMeritxell), kMeritxell);
    // At a junction the match alternates every 0.5 s for 20 s: the bar keeps the first street.
    for (int k = 0; k < 40; ++k) {
        const double from = 2.5 + 0.5 * k;
        EXPECT_EQ(frames(hold, from, from + 0.5, k % 2 == 0 ? kCarlemany : kMeritxell), kMeritxell) << "at " << from;
    }
    // Flicker (1.9 s each) from no bar: still no bar.
    StreetBarHold fresh;
    for (int k = 0; k < 10; ++k)
        EXPECT_FALSE(frames(fresh, 1.9 * k, 1.9 * (k + 1), k % 2 == 0 ? kMeritxell : kCarlemany)) << k;
    // A street's ref alone differing is another street.
    StreetBarHold refs;
    ASSERT_EQ(frames(refs, 0.0, 2.5, kMeritxell), kMeritxell);
    EXPECT_EQ(frames(refs, 2.5, 4.0, render::StreetBar{"Avinguda Meritxell", "CG-2"}), kMeritxell);
    EXPECT_EQ(frames(refs, 4.0, 5.0, render::StreetBar{"Avinguda Meritxell", "CG-2"}),
              (render::StreetBar{"Avinguda Meritxell", "CG-2"}));
}

TEST(StreetBarHold, ALostMatchKeepsTheStreetForTwoSecondsThenHidesIt) {
    StreetBarHold hold;
    ASSERT_EQ(frames(hold, 0.0, 3.0, kMeritxell), kMeritxell);
    EXPECT_EQ(frames(hold, 3.0, 4.95, std::nullopt), kMeritxell) << "kept for the hold time";
    EXPECT_FALSE(frames(hold, 4.95, 5.1, std::nullopt)) << "then hidden";
    // A short loss (1 s) keeps the street throughout.
    StreetBarHold brief;
    ASSERT_EQ(frames(brief, 0.0, 3.0, kMeritxell), kMeritxell);
    EXPECT_EQ(frames(brief, 3.0, 4.0, std::nullopt), kMeritxell);
    EXPECT_EQ(frames(brief, 4.0, 10.0, kMeritxell), kMeritxell);
    // A road with neither name nor ref counts as no street.
    StreetBarHold unnamed;
    ASSERT_EQ(frames(unnamed, 0.0, 3.0, kCarlemany), kCarlemany);
    EXPECT_FALSE(frames(unnamed, 3.0, 6.0, render::StreetBar{}));
}

TEST(StreetBarHold, PoseTimeNotCallsCountsAndABackwardJumpStartsTheWaitAgain) {
    // Two frames 2 s apart suffice; a thousand frames within 1 s do not.
    StreetBarHold sparse;
    sparse.update(kT0, kMeritxell);
    EXPECT_EQ(sparse.update(kT0 + 2.0, kMeritxell), kMeritxell);
    StreetBarHold dense;
    for (int i = 0; i < 1000; ++i) dense.update(kT0 + i * 0.001, kMeritxell);
    EXPECT_FALSE(dense.shown());
    // The pose time going back (a replay started over) restarts the wait, the bar stays.
    StreetBarHold back;
    ASSERT_EQ(frames(back, 0.0, 2.5, kMeritxell), kMeritxell);
    back.update(kT0 + 3.0, kCarlemany);
    EXPECT_EQ(back.update(kT0 - 100.0, kCarlemany), kMeritxell);
    EXPECT_EQ(back.update(kT0 - 98.5, kCarlemany), kMeritxell) << "1.5 s since the jump";
    EXPECT_EQ(back.update(kT0 - 98.0, kCarlemany), kCarlemany);
    // No time: nothing changes.
    EXPECT_EQ(back.update(std::nan(""), std::nullopt), kCarlemany);
    EXPECT_EQ(back.update(kT0 - 95.0, kCarlemany), kCarlemany);
}
