// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/road_style.h"

#include "navmap/map/road_class.h"

#include <algorithm>
#include <cmath>

namespace navmap::render {

namespace {
glm::vec3 rgb(unsigned hex) { return glm::vec3((hex >> 16) & 0xff, (hex >> 8) & 0xff, hex & 0xff) / 255.0f; }
}  // namespace

RoadStyle RoadStyle::day() {
    RoadStyle s;
    // motorway, trunk, primary, secondary, tertiary, unclassified, residential, service,
    // pedestrian, track, path. Casing on the three most important classes (issue: multi-colour).
    s.classes = {{
        {14.0f, 2.5f, rgb(0xe8925a), rgb(0x9c4a1c)},
        {12.0f, 2.0f, rgb(0xf2b36b), rgb(0xa8652a)},
        {10.0f, 1.8f, rgb(0xf7d27a), rgb(0xa0822e)},
        {8.0f, 0.0f, rgb(0xf6e7a0), rgb(0x8a8a70)},
        {7.0f, 0.0f, rgb(0xfafafa), rgb(0x808080)},
        {6.0f, 0.0f, rgb(0xf2f2f2), rgb(0x808080)},
        {5.5f, 0.0f, rgb(0xf0f0f0), rgb(0x808080)},
        {4.0f, 0.0f, rgb(0xe4e4e4), rgb(0x808080)},
        {4.0f, 0.0f, rgb(0xdcd6e8), rgb(0x808080)},
        {3.0f, 0.0f, rgb(0xc8a878), rgb(0x806040)},
        {2.0f, 0.0f, rgb(0xd8c8b0), rgb(0x806040)},
    }};
    // seed 7.3: minor roads leave distant and zoomed-out views first. Service roads, pedestrian
    // streets, tracks and paths where their true width falls to a pixel (a 2 m path at about
    // 1.2 km in the cluster's snail's view, 0.6 km on the HUD); residential and unclassified
    // roads at half a pixel (5.5 m at 6.4 km, 3.2 km). The classes above are always drawn.
    using C = map::RoadClass;
    for (const C c : {C::Unclassified, C::Residential}) s.classes[static_cast<std::size_t>(c)].select_px = 0.5f;
    for (const C c : {C::Service, C::Pedestrian, C::Track, C::Path})
        s.classes[static_cast<std::size_t>(c)].select_px = 1.0f;
    return s;
}

RoadStyle RoadStyle::night() {
    RoadStyle s = day();
    for (auto& c : s.classes) {
        c.fill *= 0.55f;
        c.casing *= 0.5f;
    }
    s.outline = glm::vec3(0.02f);
    return s;
}

float distanceWidthScale(float distance_m, float threshold_m, float max_scale) {
    if (distance_m <= threshold_m || threshold_m <= 0.0f) return 1.0f;
    return std::min(distance_m / threshold_m, max_scale);
}

SelectionFade selectionFade(float width_m, float select_px, float focal_px) {
    if (!(select_px > 0.0f)) return {};
    constexpr float kBand = kSelectionFadeBand - 1.0f;
    return {width_m * focal_px / (kBand * select_px), 1.0f / kBand};
}

std::array<SelectionFade, kStyledRoadClasses> selectionFades(const RoadStyle& style, float focal_px, bool on) {
    std::array<SelectionFade, kStyledRoadClasses> out{};
    if (!on) return out;
    for (std::size_t c = 0; c < out.size(); ++c)
        out[c] = selectionFade(style.classes[c].width_m, style.classes[c].select_px, focal_px);
    return out;
}

float leastWidthGrowthPx(float min_width_px, float width_m, float fill_width_m) {
    if (!(min_width_px > 0.0f) || !(width_m > 0.0f) || !(fill_width_m > 0.0f)) return 0.0f;
    return min_width_px * width_m / fill_width_m;
}

float capHalfLength(float segment_length, float width) { return segment_length / width; }

bool capCovers(float x, float y, float half_length) {
    const float x_cap = std::abs(x) - half_length;
    const float y_cap = std::abs(y);
    if (x_cap <= 0.0f) return y_cap <= 1.0f;
    return x_cap * x_cap + y_cap * y_cap <= 1.0f;
}

float capReach(float trimmed_reach, float half_length) {
    return half_length < kShortPieceHalfLength ? 1.0f : trimmed_reach;
}

}  // namespace navmap::render
