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
    // The street bar: darker behind, the text a little dimmer, so that it does not glare.
    s.street_bar_panel = {0.02f, 0.03f, 0.05f, 0.78f};
    s.street_bar_text = {0.86f, 0.87f, 0.90f};
    return s;
}

MapStyle MapStyle::hud() {
    MapStyle s;
    s.sky_color = {0.0f, 0.0f, 0.0f};  // transparent on the combiner
    s.route_color = {0.10f, 0.65f, 1.0f};
    s.route_casing = {0.0f, 0.0f, 0.0f};
    s.route_width_m = 8.0f;
    s.arrow_fill = {1.0f, 1.0f, 1.0f};
    s.arrow_casing = {0.0f, 0.0f, 0.0f};
    s.guidance_road_color = {0.62f, 0.66f, 0.72f};
    s.guidance_panel = {0.0f, 0.0f, 0.0f, 0.0f};
    s.guidance_symbol = {1.0f, 1.0f, 1.0f};
    s.guidance_symbol_dim = {0.42f, 0.46f, 0.52f};
    s.guidance_text = {1.0f, 1.0f, 1.0f};
    return s;
}

MapLayers MapLayers::hud() {
    MapLayers l;
    l.terrain = false;
    l.land_cover = false;
    l.roads = false;
    l.outlines = false;
    l.buildings = false;
    l.labels = false;
    l.glow_roads = false;
    l.label_aura = false;
    l.marker = false;
    l.route = true;
    return l;
}

}  // namespace navmap::render
