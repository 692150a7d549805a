// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the sun stands for a place and a time: its elevation above the horizon, by the NOAA
// solar calculator's low-precision algorithm (docs/rendering.md "Day and night"). Pure
// arithmetic; reads no clock.

#include <chrono>

namespace navmap::daemon {

/// The sun's geometric elevation, degrees (the centre of its disc, without atmospheric
/// refraction: civil twilight ends at -6 degrees of it), at latitude `lat_deg` and longitude
/// `lon_deg` (WGS84, east positive) at the instant `t`.
///
/// The NOAA Global Monitoring Laboratory's solar calculator (gml.noaa.gov/grad/solcalc, its
/// "NOAA_Solar_Calculations_day.xls"), which takes its series from J. Meeus, "Astronomical
/// Algorithms" (2nd ed., 1998), chapters 25 (the sun's low-accuracy position: mean longitude,
/// mean anomaly, equation of centre, apparent longitude, corrected obliquity, declination) and 28
/// (equation of time): within about 0.01 degrees of declination from 1800 to 2100, UT standing in
/// for TT (69 s, under 0.005 degrees). Elevations agree with the published values to within 0.2
/// degrees (tests/daemon/sun_position_test.cpp), plenty for a threshold of -6.
double solarElevationDeg(double lat_deg, double lon_deg, std::chrono::system_clock::time_point t);

}  // namespace navmap::daemon
