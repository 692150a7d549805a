// SPDX-License-Identifier: Apache-2.0
#pragma once
// MapMatcher: snaps a position onto the road graph: the nearest drivable edge segment with
// heading agreement, with hysteresis towards the previously matched edge and its neighbours.
// A uniform grid over the edge segments keeps a query near constant time. Immutable after
// construction: share it between threads.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "navmap/daemon/vehicle/vehicle_state_config.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"

namespace navmap::daemon {

struct RoadMatch {
    std::uint32_t edge = 0;    ///< index into RoadGraph::edges (direction of travel)
    map::PlanarPoint point;    ///< nearest point on the edge
    double heading_deg = 0.0;  ///< direction of the edge there (clockwise from north)
    double distance_m = 0.0;
    double confidence = 0.0;  ///< 0..1: distance and heading agreement
    double score = 0.0;       ///< lower is better (includes the hysteresis bonuses)
};

/// exp(-d^2/2s_d^2) * exp(-dh^2/2s_h^2): the confidence of a candidate (heading term only when
/// `useHeading`).
double matchConfidence(double distance_m, double heading_diff_deg, bool use_heading, const VehicleStateConfig& cfg);

class MapMatcher {
public:
    explicit MapMatcher(std::shared_ptr<const map::RoadGraph> graph, double cell_m = 50.0);

    /// Best candidate within cfg.match_radius_m, or nullopt. `heading_deg` counts when set;
    /// `previousEdge` gets cfg.hysteresis_bonus, edges continuing from it cfg.connected_bonus.
    [[nodiscard]] std::optional<RoadMatch> match(map::PlanarPoint p, std::optional<double> heading_deg,
                                                 std::optional<std::uint32_t> previous_edge,
                                                 const VehicleStateConfig& cfg) const;

    [[nodiscard]] const map::RoadGraph& graph() const { return *m_graph; }
    [[nodiscard]] std::size_t segmentCount() const { return m_segments.size(); }

private:
    struct Seg {
        map::PlanarPoint a, b;  // in the edge's direction of travel
        std::uint32_t edge;
    };
    std::shared_ptr<const map::RoadGraph> m_graph;
    std::vector<Seg> m_segments;
    double m_cell;
    double m_min_x = 0, m_min_y = 0;
    int m_cols = 0, m_rows = 0;
    std::vector<std::uint32_t> m_cell_start;  // CSR over cells
    std::vector<std::uint32_t> m_cell_segs;
};

}  // namespace navmap::daemon
