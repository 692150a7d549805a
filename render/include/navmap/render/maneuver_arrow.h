// SPDX-License-Identifier: Apache-2.0
#pragma once
// Route guidance on the map, GL-free: the manoeuvre arrow cut from the route, its shape
// prepared for draping (the shaft, the head and the casing's reach beyond the tip), and the
// road pieces around a junction that the head-up display's guidance style shows.

#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "navmap/map/tile.h"
#include "navmap/render/map_frame.h"

namespace navmap::render {

/// The arrow of the manoeuvre `junction_measure_m` along `route`: the route from
/// junction - before_m to junction + after_m (clamped to the route), with points interpolated at
/// both ends (e.g. 40 m before and 25 m after: a shaft along the incoming road, the turn, and
/// the outgoing road, which the head ends on). Emphasis 1. No points when the route has fewer than
/// two points or measures that do not match them, or when less than 1 m of it is left.
ManeuverArrow cutManeuverArrow(const RouteGeometry& route, double junction_measure_m, double before_m, double after_m);

/// The pieces of the roads of `tiles` within `radius_m` of `junction` (store-frame x, y): each
/// road polyline clipped to the disc, one polyline per piece inside (z 0: draped when drawn).
/// Tunnels are left out (they are not on the surface). For MapFrame::guidance_roads: in the HUD
/// style, the roads that branch at the next junction (60 m is a good radius).
std::vector<std::vector<glm::dvec3>> junctionRoads(std::span<const std::shared_ptr<const map::Tile>> tiles,
                                                   glm::dvec2 junction, double radius_m);

/// An arrow ready to drape: its polyline with measures from 0 at the tail, vertices at every
/// measure where the width changes its slope (so that each draped piece's width is linear between
/// its ends), and extended straight beyond the tip by the casing's reach.
struct ArrowShape {
    RouteGeometry line;
    double head_m = 0.0;             ///< the head's base (the shaft ends here)
    double tip_m = 0.0;              ///< the fill's tip
    double casing_tip_m = 0.0;       ///< the casing's tip (end of `line`)
    float half_width_m = 0.0f;       ///< shaft fill, half width
    float head_half_width_m = 0.0f;  ///< head fill at its base, half width
    float casing_m = 0.0f;           ///< casing per side
};

/// The shape of `arrow` with the widths of `style` (arrow_*) times `scale` (the renderer grows
/// distant arrows); an empty line when the arrow has fewer than two distinct points. The head
/// takes MapStyle::arrow_head_length_m times `scale`, at most a third of the arrow's length (then
/// narrowed in proportion).
ArrowShape arrowShape(const ManeuverArrow& arrow, const MapStyle& style, float scale = 1.0f);

/// The `scale` the renderer draws `arrow` with: as the route at its distance from `eye` (seed
/// 3.6.3), and at least MapStyle::arrow_min_width_px wide where it is far below (bird's-eye).
/// `ground_z`: the height the arrow's points are taken at (they carry none); `focal_px`: the
/// projection's focal length in pixels (projection[1][1] * viewport height / 2).
float arrowScale(const ManeuverArrow& arrow, const MapStyle& style, const glm::dvec3& eye, double ground_z,
                 float focal_px);

/// Half width of the arrow at `measure_m`, metres: `casing` true for the casing (the fill grown
/// by casing_m on every side, the head's tip beyond the fill's). At a measure where the width
/// jumps (the head's base), `after` picks the side beyond it. arrow_geo.vert computes the same.
float arrowHalfWidth(const ArrowShape& shape, double measure_m, bool casing, bool after);

}  // namespace navmap::render
