// SPDX-License-Identifier: Apache-2.0
#include "sun_position.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace navmap::daemon {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double wrapDeg(double a) {
    a = std::fmod(a, 360.0);
    return a < 0.0 ? a + 360.0 : a;
}

}  // namespace

double solarElevationDeg(double lat_deg, double lon_deg, std::chrono::system_clock::time_point t) {
    // Days since the Unix epoch, and Julian centuries since J2000.0 (JD 2451545.0).
    const double unix_days = std::chrono::duration<double>(t.time_since_epoch()).count() / 86400.0;
    const double jd = unix_days + 2440587.5;
    const double c = (jd - 2451545.0) / 36525.0;
    // Meeus 25.2-25.4: geometric mean longitude, mean anomaly, eccentricity of the orbit.
    const double l0 = wrapDeg(280.46646 + c * (36000.76983 + c * 0.0003032));
    const double m = 357.52911 + c * (35999.05029 - 0.0001537 * c);
    const double e = 0.016708634 - c * (0.000042037 + 0.0000001267 * c);
    // The equation of centre, the true and the apparent longitude (nutation and aberration).
    const double centre = std::sin(m * kDeg) * (1.914602 - c * (0.004817 + 0.000014 * c)) +
                          std::sin(2.0 * m * kDeg) * (0.019993 - 0.000101 * c) + std::sin(3.0 * m * kDeg) * 0.000289;
    const double omega = 125.04 - 1934.136 * c;
    const double apparent_lon = l0 + centre - 0.00569 - 0.00478 * std::sin(omega * kDeg);
    // Meeus 22.2: mean obliquity of the ecliptic, corrected for nutation (25.8).
    const double obliquity0 = 23.0 + (26.0 + (21.448 - c * (46.815 + c * (0.00059 - c * 0.001813))) / 60.0) / 60.0;
    const double obliquity = obliquity0 + 0.00256 * std::cos(omega * kDeg);
    const double declination = std::asin(std::sin(obliquity * kDeg) * std::sin(apparent_lon * kDeg));
    // Meeus 28.3: the equation of time, minutes.
    const double y = std::pow(std::tan(obliquity * kDeg / 2.0), 2.0);
    const double eq_time_min = 4.0 / kDeg *
                               (y * std::sin(2.0 * l0 * kDeg) - 2.0 * e * std::sin(m * kDeg) +
                                4.0 * e * y * std::sin(m * kDeg) * std::cos(2.0 * l0 * kDeg) -
                                0.5 * y * y * std::sin(4.0 * l0 * kDeg) - 1.25 * e * e * std::sin(2.0 * m * kDeg));
    // True solar time at the longitude, and the hour angle (0 at local apparent noon).
    const double minutes_of_day = (unix_days - std::floor(unix_days)) * 1440.0;
    const double true_solar_min = std::fmod(minutes_of_day + eq_time_min + 4.0 * lon_deg + 2880.0, 1440.0);
    const double hour_angle = true_solar_min / 4.0 - 180.0;
    const double lat = lat_deg * kDeg;
    const double cos_zenith =
        std::sin(lat) * std::sin(declination) + std::cos(lat) * std::cos(declination) * std::cos(hour_angle * kDeg);
    return 90.0 - std::acos(std::clamp(cos_zenith, -1.0, 1.0)) / kDeg;
}

}  // namespace navmap::daemon
