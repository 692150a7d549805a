// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/style_fade.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace navmap::render {

namespace {

// a (1 - t) + b t: exactly a at 0 and exactly b at 1.
template <typename T>
T mixValue(const T& a, const T& b, float t) {
    return a * (1.0f - t) + b * t;
}

void mixRoads(RoadStyle& out, const RoadStyle& a, const RoadStyle& b, float t) {
    for (std::size_t i = 0; i < out.classes.size(); ++i) {
        out.classes[i].fill = mixValue(a.classes[i].fill, b.classes[i].fill, t);
        out.classes[i].casing = mixValue(a.classes[i].casing, b.classes[i].casing, t);
    }
    out.outline = mixValue(a.outline, b.outline, t);
    out.outline_strength = mixValue(a.outline_strength, b.outline_strength, t);
}

}  // namespace

MapStyle mixStyles(const MapStyle& from, const MapStyle& to, float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    if (t == 0.0f) return from;
    if (t == 1.0f) return to;
    MapStyle s = t < 0.5f ? from : to;
    s.sky_color = mixValue(from.sky_color, to.sky_color, t);
    s.brightness = mixValue(from.brightness, to.brightness, t);
    s.far_ground_color = mixValue(from.far_ground_color, to.far_ground_color, t);
    mixRoads(s.roads, from.roads, to.roads, t);
    s.route_color = mixValue(from.route_color, to.route_color, t);
    s.route_casing = mixValue(from.route_casing, to.route_casing, t);
    s.marker_color = mixValue(from.marker_color, to.marker_color, t);
    s.marker_stale_color = mixValue(from.marker_stale_color, to.marker_stale_color, t);
    s.glow_color = mixValue(from.glow_color, to.glow_color, t);
    s.glow_strength = mixValue(from.glow_strength, to.glow_strength, t);
    s.arrow_fill = mixValue(from.arrow_fill, to.arrow_fill, t);
    s.arrow_casing = mixValue(from.arrow_casing, to.arrow_casing, t);
    s.guidance_road_color = mixValue(from.guidance_road_color, to.guidance_road_color, t);
    s.guidance_panel = mixValue(from.guidance_panel, to.guidance_panel, t);
    s.guidance_symbol = mixValue(from.guidance_symbol, to.guidance_symbol, t);
    s.guidance_symbol_dim = mixValue(from.guidance_symbol_dim, to.guidance_symbol_dim, t);
    s.guidance_text = mixValue(from.guidance_text, to.guidance_text, t);
    s.street_bar_panel = mixValue(from.street_bar_panel, to.street_bar_panel, t);
    s.street_bar_text = mixValue(from.street_bar_text, to.street_bar_text, t);
    return s;
}

void StyleFade::reset(bool night) {
    m_from = m_to = night ? 1.0f : 0.0f;
    m_start_s = 0.0;
}

void StyleFade::target(bool night, double now_s) {
    const float to = night ? 1.0f : 0.0f;
    if (to == m_to) return;
    m_from = weightAt(now_s);
    m_to = to;
    m_start_s = now_s;
}

float StyleFade::weightAt(double now_s) const {
    const double span_s = m_duration_s * std::abs(double(m_to) - double(m_from));
    if (!(span_s > 0.0) || now_s - m_start_s >= span_s) return m_to;
    const double done = std::max(0.0, (now_s - m_start_s) / span_s);
    return static_cast<float>(double(m_from) + (double(m_to) - double(m_from)) * done);
}

}  // namespace navmap::render
