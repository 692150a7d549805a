// SPDX-License-Identifier: Apache-2.0
#pragma once
// OffRouteDetector: off-route with hysteresis (docs/guidance.md "Off route"). The vehicle is off
// the route after it has been farther than leave_distance_m from it for leave_time_s without a
// break, and on it again after it has been within return_distance_m for return_time_s. A pure
// function of the sample stream (its timestamps, no clock); one instance per stream, not
// thread-safe.

#include <cstddef>
#include <optional>
#include <string>

namespace navmap::map::guidance {

struct OffRouteConfig {
    double leave_distance_m = 40.0;
    double leave_time_s = 3.0;
    double return_distance_m = 20.0;  ///< below leave_distance_m: the band between holds the state
    double return_time_s = 2.0;

    /// Why the configuration is unusable ("return_distance_m 50 must be below leave_distance_m
    /// 40"), or "" when it is fine.
    [[nodiscard]] std::string problem() const;
};

class OffRouteDetector {
public:
    /// Throws std::runtime_error with problem() for an unusable configuration.
    explicit OffRouteDetector(OffRouteConfig config = {});

    /// One sample: time in seconds (any epoch, non-decreasing) and the distance from the pose
    /// to the route in metres (RouteProgress::offset_m). Returns whether the vehicle is off the
    /// route. A non-finite sample or one older than the previous is ignored and counted.
    bool update(double time_s, double distance_m);
    /// Back on the route, no pending change (a new route).
    void reset();

    [[nodiscard]] bool offRoute() const { return m_off; }
    [[nodiscard]] std::size_t ignoredSamples() const { return m_ignored; }
    [[nodiscard]] const OffRouteConfig& config() const { return m_config; }

private:
    OffRouteConfig m_config;
    bool m_off = false;
    std::optional<double> m_candidate_since;  // start of the current run of samples beyond the threshold
    std::optional<double> m_last_time;
    std::size_t m_ignored = 0;
};

}  // namespace navmap::map::guidance
