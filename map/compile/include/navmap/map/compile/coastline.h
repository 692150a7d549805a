// SPDX-License-Identifier: Apache-2.0
#pragma once
// Land and sea from natural=coastline ways, by the rules of the common OSM toolchains
// (osmcoastline): the water lies on the right of a way's direction, ways are joined where they
// share an end node, small gaps are closed, and coastlines that leave the data are closed along
// its bounding box. docs/tile-store.md "Coast" describes the rules.
//
// Hand-written: libosmium assembles multipolygons from relations but not coastlines (that is
// osmcoastline, a program, not a library), and no Debian library joins open coastlines along a
// box. The result is plain rings; tiling and triangulation use the compiler's usual clipRing
// and CGAL triangulation (odd winding).

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/map/geometry.h"

namespace navmap::map {

/// One natural=coastline way (or one run of it with node locations), in planar metres.
struct CoastWay {
    std::int64_t id = 0;
    std::int64_t first_node = 0, last_node = 0;
    std::vector<PlanarPoint> points;  ///< in the way's direction: land left, water right
};

struct Coast {
    /// Counter-clockwise rings of the sea, within the box. Odd winding together with `islands`.
    std::vector<std::vector<PlanarPoint>> sea;
    /// Clockwise rings of land inside the sea (closed coastline rings: islands).
    std::vector<std::vector<PlanarPoint>> islands;
    std::size_t gaps_closed = 0;    ///< joins of way ends that were apart by up to close_m
    std::size_t ways_left_out = 0;  ///< ways of broken coastlines that could not be repaired
    std::vector<std::string> warnings;
    [[nodiscard]] bool empty() const { return sea.empty(); }
};

/// Assembles the sea within `box` (the data's bounding box, planar metres). Ways that share an
/// end node are joined; an end within `close_m` of another chain's start (its own included) is
/// joined to it; chains whose both ends lie within `close_m` of the box's border are closed along
/// the border, going round it clockwise from the end (the water side); any other open chain is
/// broken: it is left out (land) with a warning naming its way ids.
Coast assembleCoast(std::vector<CoastWay> ways, const Box& box, double close_m);

/// Which samples of an n x n grid (row 0 at y0, column 0 at x0, `spacing` apart) lie inside the
/// rings by the odd winding rule (row-major, 1 = inside). A scanline fill over the ring edges.
std::vector<char> samplesInside(const std::vector<std::vector<PlanarPoint>>& rings, double x0, double y0,
                                double spacing, int n);

}  // namespace navmap::map
