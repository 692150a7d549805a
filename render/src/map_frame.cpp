// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/map_frame.h"

namespace navmap::render {

MapStyle MapStyle::day() { return MapStyle{}; }

MapStyle MapStyle::night() {
    MapStyle s;
    s.sky_color = {0.05f, 0.07f, 0.13f};
    s.brightness = 0.45f;
    s.roads = RoadStyle::night();
    s.route_color = {0.25f, 0.65f, 1.0f};
    s.route_casing = {0.05f, 0.15f, 0.35f};
    s.glow_color = {0.35f, 0.95f, 1.0f};
    return s;
}

}  // namespace navmap::render
