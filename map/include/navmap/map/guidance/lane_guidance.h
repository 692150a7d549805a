// SPDX-License-Identifier: Apache-2.0
#pragma once
// Lane guidance (docs/guidance.md "Lanes"): for each manoeuvre of a route, the turn lanes of the
// last way before its junction that has them (walking back along the route on the road graph,
// within a distance), and which of those lanes lead to the manoeuvre's exit. LaneFinder indexes a
// graph once and is then read-only (thread-safe to share); the functions are pure.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "navmap/map/guidance/maneuver.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"

namespace navmap::map::guidance {

/// The lanes shown before one manoeuvre.
struct LaneGuidance {
    std::vector<std::uint16_t> lanes;  ///< lane_arrow bits per lane, left to right (turn_lanes.h)
    std::uint32_t recommended = 0;     ///< bit i: lane i leads to the manoeuvre's exit
    double before_junction_m = 0.0;    ///< along the route from the tagged edge's end to the junction
    std::int64_t way_id = 0;           ///< the OSM way the lanes are tagged on
    friend bool operator==(const LaneGuidance&, const LaneGuidance&) = default;
};

/// Which of `lanes` lead out along a manoeuvre of `type` (roundabouts, exits and merges by the
/// class of `turn_deg`, their heading change): bit i for lane i. The lanes whose arrows point the
/// manoeuvre's way; else the neighbouring arrows (a left turn: sharp or slight left; straight:
/// lanes without arrows); else none. A lane that merges away is never recommended to go straight.
std::uint32_t recommendedLanes(std::span<const std::uint16_t> lanes, ManeuverType type, double turn_deg);

struct LaneSearchOptions {
    /// Lanes are taken from an edge ending at most this far before the junction, metres
    /// ([guidance] lane_distance_m).
    double distance_m = 500.0;
    /// A graph node or shape point within this distance of the route lies on it, metres.
    double match_m = 5.0;
    /// Work bound for one find(): point-to-segment tests over all manoeuvres (a route of
    /// thousands of points a few metres apart would take seconds otherwise); the manoeuvres left
    /// when it is spent get no lanes.
    std::size_t max_tests = 20'000'000;
};

/// Finds the route's edges on one road graph by their geometry, as routes come as points (the
/// control protocol's set_route) without the edges they follow.
class LaneFinder {
public:
    /// `graph` must outlive the finder and stay unchanged.
    explicit LaneFinder(const RoadGraph& graph);

    /// One entry per manoeuvre of a route through `points` (store frame): its lanes, or nullopt
    /// where no edge with lanes lies within the distance before its junction and after the
    /// previous manoeuvre's end (also for depart, arrive, and where the route leaves the graph).
    [[nodiscard]] std::vector<std::optional<LaneGuidance>> find(const std::vector<PlanarPoint>& points,
                                                                const std::vector<Maneuver>& maneuvers,
                                                                const LaneSearchOptions& options = {}) const;

private:
    [[nodiscard]] std::optional<std::uint32_t> nodeNear(PlanarPoint p, double within_m) const;
    [[nodiscard]] std::optional<LaneGuidance> lanesBefore(const std::vector<PlanarPoint>& points,
                                                          const std::vector<double>& measures, const Maneuver& m,
                                                          std::size_t previous_end, const LaneSearchOptions& options,
                                                          std::size_t& tests_left) const;

    const RoadGraph& m_graph;
    std::vector<std::uint32_t> m_in_first;  // CSR by `to`: edges into node n are m_in[m_in_first[n]..)
    std::vector<std::uint32_t> m_in;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> m_cells;  // nodes per grid cell
};

}  // namespace navmap::map::guidance
