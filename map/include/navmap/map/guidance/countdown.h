// SPDX-License-Identifier: Apache-2.0
#pragma once
// The distance countdown to the next manoeuvre (docs/guidance.md "Countdown"): the announced
// distance never exceeds the true one, steps 800, 500, 300, 200, 100, 50 m, then "now". Pure
// functions, thread-safe.

#include <array>
#include <string>

namespace navmap::map::guidance {

/// The countdown steps in metres, largest first.
inline constexpr std::array<double, 6> kCountdownStepsM{800.0, 500.0, 300.0, 200.0, 100.0, 50.0};
/// Below this distance the manoeuvre is "now", metres.
inline constexpr double kCountdownNowM = 20.0;

struct Countdown {
    enum class Kind { Invalid, Now, Metres, Kilometres };
    Kind kind = Kind::Invalid;
    /// Metres: the step (50 .. 800). Kilometres: the distance rounded down to 0.1 km below
    /// 10 km and to 1 km from 10 km on (1.2, 12). Now / Invalid: 0.
    double value = 0.0;
    friend bool operator==(const Countdown&, const Countdown&) = default;
};

/// The announced distance for `distance_m` metres left:
///   d < 20 m                 -> Now (negative distances too: the manoeuvre is here or passed)
///   20 m <= d < 100 m        -> 50 m (the last step holds until "now")
///   50 <= step <= d < next   -> the largest step not above d (100, 200, 300, 500, 800 m)
///   1 km <= d < 10 km        -> d rounded down to 0.1 km
///   d >= 10 km               -> d rounded down to 1 km
///   NaN or infinite          -> Invalid
Countdown countdownFor(double distance_m) noexcept;

/// "now", "300 m", "1.2 km", "12 km"; "" for Invalid.
std::string formatCountdown(const Countdown& c);
inline std::string formatCountdown(double distance_m) { return formatCountdown(countdownFor(distance_m)); }

}  // namespace navmap::map::guidance
