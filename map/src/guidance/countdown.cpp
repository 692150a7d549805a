// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/countdown.h"

#include <cmath>
#include <cstdio>

namespace navmap::map::guidance {

Countdown countdownFor(double d) noexcept {
    if (!std::isfinite(d)) return {};
    if (d < kCountdownNowM) return {Countdown::Kind::Now, 0.0};
    if (d >= 10000.0) return {Countdown::Kind::Kilometres, std::floor(d / 1000.0)};
    // Whole hundreds of metres first, so that 1.2 km is exactly 12 tenths and prints as such.
    if (d >= 1000.0) return {Countdown::Kind::Kilometres, std::floor(d / 100.0) / 10.0};
    for (const double step : kCountdownStepsM) {
        if (d >= step) return {Countdown::Kind::Metres, step};
    }
    return {Countdown::Kind::Metres, kCountdownStepsM.back()};
}

std::string formatCountdown(const Countdown& c) {
    char buf[32];
    switch (c.kind) {
        case Countdown::Kind::Invalid: return {};
        case Countdown::Kind::Now: return "now";
        case Countdown::Kind::Metres: std::snprintf(buf, sizeof buf, "%.0f m", c.value); return buf;
        case Countdown::Kind::Kilometres:
            std::snprintf(buf, sizeof buf, c.value >= 10.0 ? "%.0f km" : "%.1f km", c.value);
            return buf;
    }
    return {};
}

}  // namespace navmap::map::guidance
