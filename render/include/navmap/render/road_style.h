// SPDX-License-Identifier: Apache-2.0
#pragma once
// Cartographic road styling (seed 3.4 caps, 3.6.3 scaling and multi-colour roads): widths and
// colours per functional road class, the analytic cap test and distance-based width scaling.
// The shaders roads_geo.vert/.frag implement the same formulas; these CPU versions are the
// reference the unit tests check.

#include <algorithm>
#include <array>
#include <limits>

#include <glm/glm.hpp>

namespace navmap::render {

/// Number of road classes styled (matches navmap::map::kRoadClassCount).
inline constexpr int kStyledRoadClasses = 11;

struct RoadClassStyle {
    float width_m = 4.0f;   ///< fill width on the ground, metres
    float casing_m = 0.0f;  ///< extra width of the casing on each side (0: no casing)
    glm::vec3 fill{1.0f};
    glm::vec3 casing{0.3f};
    /// seed 7.3, "adaptive filtering of the roads": minor roads are left out of far and zoomed-out
    /// views before major ones. The class is left out where its true width (width_m, before the
    /// distance scaling of 3.6.3) covers at most this on screen, pixels; 0: always drawn. It
    /// fades rather than pops: the drawn width shrinks to nothing as the true width falls from
    /// kSelectionFadeBand times this to it (selectionFade()).
    float select_px = 0.0f;

    /// Full width of the widest pass on the ground (with the casing where there is one), metres.
    [[nodiscard]] float outerWidth() const { return width_m + 2.0f * std::max(casing_m, 0.0f); }
};

/// The style table, most important class first (index = map::RoadClass value).
struct RoadStyle {
    std::array<RoadClassStyle, kStyledRoadClasses> classes{};
    float scale_threshold_m = 1500.0f;  ///< seed 3.6.3: no width scaling closer than this
    float max_scale = 12.0f;            ///< distant roads grow at most this much
    float z_offset_alpha = 0.02f;       ///< seed 3.6.2: view-space scale (1 - alpha)
    /// Least on-screen width of a road's fill, pixels (0: none): far roads seen at a grazing angle
    /// are widened across to it, so that they do not break up into dashes (roads_geo.vert). A
    /// tenth over one pixel: a band of exactly one pixel misses both pixel centres of a column
    /// where rounding puts its edges on them.
    float min_width_px = 1.1f;
    glm::vec3 outline{0.12f, 0.12f, 0.14f};  ///< seed 3.6.3 dark outline colour
    float outline_strength = 0.75f;

    /// The style of a road class value (map::RoadClass), clamped to the table.
    [[nodiscard]] const RoadClassStyle& of(int road_class) const {
        return classes[static_cast<std::size_t>(std::clamp(road_class, 0, kStyledRoadClasses - 1))];
    }

    static RoadStyle day();
    static RoadStyle night();
};

/// seed 3.6.3 "Scaling": widths grow linearly with the distance to the viewer beyond a
/// threshold, so distant roads stay visible while near ones keep their true width.
float distanceWidthScale(float distance_m, float threshold_m, float max_scale);

/// The most roads_geo.vert moves a quad's upper side beyond its projection, in pixels, where it
/// widens a foreshortened road's fill to `min_width_px` on screen (RoadStyle::min_width_px): that
/// width times the pass's share of the fill, `width_m` / `fill_width_m` (the casing grows in
/// proportion). 0 where any of them is not positive.
float leastWidthGrowthPx(float min_width_px, float width_m, float fill_width_m);

/// Where a selected class starts to fade (RoadClassStyle::select_px): at this many times its
/// threshold.
inline constexpr float kSelectionFadeBand = 1.5f;

/// seed 7.3 for one class and view: the share of its drawn width a road keeps at a distance d
/// from the eye, clamp(a / d - b, 0, 1). With true width w, threshold s and focal length f
/// (pixels: the viewport height over twice the tangent of half the vertical field of view) the
/// true width covers w f / d pixels, and the share is 1 from kSelectionFadeBand * s pixels up, 0
/// at s and below, linear in the true width between: a = w f / ((band - 1) s), b = 1 / (band - 1).
/// Where s is not positive a = 0, b = -1: always 1. The road shaders evaluate the same line per
/// quad (roads_geo.vert) or pixel (roads_sv.frag) from u_select.
struct SelectionFade {
    float a = 0.0f, b = -1.0f;

    [[nodiscard]] float at(float distance_m) const {
        if (!(distance_m > 0.0f)) return 1.0f;  // at the eye: as wide as can be
        return std::clamp(a / distance_m - b, 0.0f, 1.0f);
    }
    /// The distance from which the share is 0 (infinity: never).
    [[nodiscard]] float goneFromM() const { return b > 0.0f ? a / b : std::numeric_limits<float>::infinity(); }
};
SelectionFade selectionFade(float width_m, float select_px, float focal_px);

/// Every class's selectionFade() for a view of focal length `focal_px`, the fill width being the
/// true width; `on` false (MapLayers::road_selection off): always 1.
std::array<SelectionFade, kStyledRoadClasses> selectionFades(const RoadStyle& style, float focal_px, bool on);

/// seed 3.4 in the coordinates roads_geo.vert hands its fragments: the half length L = d / w of
/// a segment of length d and width w, in half widths.
float capHalfLength(float segment_length, float width);

/// seed 3.4: whether the point (x, y) of a segment's quad is covered by the road with rounded
/// caps, x along the segment and y across, both in half widths from its centre (the quad spans
/// |x| <= L + 1, |y| <= 1): x_cap = |x| - L, y_cap = |y|; outside the cap region (x_cap <= 0)
/// always covered, inside covered when x_cap^2 + y_cap^2 <= 1. (The seed's quad-local x_q in
/// [-1, 1] and cap ratio h = w / (d + w) give x_cap = (|x_q| - 1) / h + 1, the same with
/// x = x_q (L + 1); roads_geo.frag.)
bool capCovers(float x, float y, float half_length);

/// How far a quad reaches beyond one end, in half widths, from its piece's RoadInstance::cap_reach
/// there: a piece shorter than its half width keeps both whole caps, as its body does not cover the
/// half of the round join behind the joint that its neighbour's trimmed quad leaves to it
/// (roads_geo.vert; the width is known only when drawing, scaled by the distance).
float capReach(float trimmed_reach, float half_length);
/// Half length (in half widths) under which a piece counts as short for capReach: half its width
/// plus a margin.
inline constexpr float kShortPieceHalfLength = 0.55f;

}  // namespace navmap::render
