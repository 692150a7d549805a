// SPDX-License-Identifier: Apache-2.0
#pragma once
// RouteProgressTracker: where the vehicle is along a GuidanceRoute (docs/guidance.md
// "Progress"): the pose projected onto the route polyline within a window around the previous
// match, so a route that passes a place twice is followed in order; progress never goes back;
// the next manoeuvre, the distances and the time left. One instance per pose stream, not
// thread-safe; the route it reads is immutable and shared.

#include <cstddef>
#include <memory>
#include <optional>

#include "navmap/map/guidance/guidance_route.h"

namespace navmap::map::guidance {

struct ProgressConfig {
    double back_window_m = 50.0;      ///< a match may lie this far behind the progress
    double forward_window_m = 500.0;  ///< and this far ahead of it
    /// When the best match in the window is farther than this from the pose, the rest of the
    /// route ahead is searched too (after a GNSS gap or a long off-route stretch).
    double reacquire_m = 50.0;
    double pass_after_m = 10.0;     ///< a manoeuvre is passed this far beyond its end point
    double arrive_radius_m = 20.0;  ///< arrived when this little of the route is left
};

struct RouteProgress {
    double measure_m = 0.0;        ///< progress along the route, metres (never decreases)
    double match_measure_m = 0.0;  ///< where this pose projected (may lie up to back_window_m behind)
    PlanarPoint on_route;          ///< the projected point
    double offset_m = 0.0;         ///< distance from the pose to the route
    double remaining_m = 0.0;      ///< to the destination
    double remaining_s = 0.0;      ///< to the destination at the route's segment speeds
    std::size_t passed = 0;        ///< manoeuvres passed (GuidanceRoute::maneuvers()[0 .. passed))
    /// Index of the next manoeuvre to announce (never Depart), nullopt when none is left.
    std::optional<std::size_t> next;
    double to_next_m = 0.0;  ///< to the next manoeuvre's point; 0 while in it (a roundabout)
    bool arrived = false;
};

class RouteProgressTracker {
public:
    /// `route` must not be null.
    explicit RouteProgressTracker(std::shared_ptr<const GuidanceRoute> route, ProgressConfig config = {});

    /// Projects a store-frame position (the map-matched pose) and returns the new progress.
    /// Non-finite positions are ignored (the previous progress is returned, counted).
    const RouteProgress& update(PlanarPoint pose);
    /// Forgets the progress: the next update searches the whole route.
    void reset();

    [[nodiscard]] const RouteProgress& progress() const { return m_progress; }
    [[nodiscard]] const GuidanceRoute& route() const { return *m_route; }
    [[nodiscard]] std::size_t ignoredPoses() const { return m_ignored; }
    [[nodiscard]] std::size_t reacquisitions() const { return m_reacquired; }

private:
    struct Match {
        double measure = 0.0;
        double distance = 0.0;
        PlanarPoint point;
    };
    [[nodiscard]] std::optional<Match> nearest(PlanarPoint p, double from_m, double to_m) const;
    void fill(double match_measure, const Match& m);

    std::shared_ptr<const GuidanceRoute> m_route;
    ProgressConfig m_config;
    RouteProgress m_progress;
    bool m_started = false;
    std::size_t m_ignored = 0;
    std::size_t m_reacquired = 0;
};

}  // namespace navmap::map::guidance
