// SPDX-License-Identifier: Apache-2.0
#include "label_text_style.h"

#include <algorithm>
#include <array>

#include "navmap/map/feature_classes.h"

namespace navmap::render::text {

namespace {

// seed 4.5.2: a dark outline for contrast against any background (Fig. 4.7a) and a light halo
// clearing the space around the label (Fig. 4.7c); large, light type for legibility.
TextStyle baseStyle(glm::vec4 fill) {
    TextStyle s;
    s.fill = fill;
    s.outline = glm::vec4(0.08f, 0.08f, 0.10f, 1.0f);
    s.outline_px = 1.2f;
    s.halo = glm::vec4(1.0f, 1.0f, 1.0f, 0.45f);
    s.halo_px = 2.5f;
    return s;
}

}  // namespace

// Sizes for a car display read at arm's length (docs/labels.md, "Text sizes"): DejaVu Sans has
// a cap height of 0.73 em, so 15 px type has 11 px capitals, about 11.5 arc minutes on a
// 12.3-inch 1280 x 480 cluster seen from 75 cm; street names 15-17 px, places 15-30 px by rank.
// The layout never scales capitals below 9.5 px (LayoutParams::min_cap_height_px).
LabelTextStyle labelTextStyle(map::LabelKind kind, std::uint8_t subclass) {
    LabelTextStyle l;
    switch (kind) {
        case map::LabelKind::Place: {
            // Size by class, largest first (PlaceClass order): Country ... Other.
            constexpr std::array<float, 12> kSizes = {30, 28, 26, 23, 19, 17, 16, 15, 15, 15, 16, 15};
            l.font =
                subclass <= static_cast<std::uint8_t>(map::PlaceClass::Village) ? FontStyle::Bold : FontStyle::Regular;
            l.size_px = kSizes[std::min<std::size_t>(subclass, kSizes.size() - 1)];
            constexpr std::array<float, 12> kReach = {12, 12, 10, 6, 5, 4, 3.5, 3.5, 3.5, 3, 5, 3};
            l.world_reach = kReach[std::min<std::size_t>(subclass, kReach.size() - 1)];
            l.style = baseStyle(glm::vec4(1.0f, 1.0f, 1.0f, 1.0f));
            break;
        }
        case map::LabelKind::Poi: {
            // Symbols DejaVu Sans has: amenity ●, shop ■, tourism ★, leisure ♣, historic ⌂,
            // office ◆, peak ▲ (PoiClass order).
            constexpr std::array<const char*, 7> kIcons = {"\u25CF", "\u25A0", "\u2605", "\u2663",
                                                           "\u2302", "\u25C6", "\u25B2"};
            constexpr std::array<glm::vec4, 7> kColors = {
                glm::vec4(0.85f, 0.45f, 0.15f, 1.0f), glm::vec4(0.65f, 0.35f, 0.75f, 1.0f),
                glm::vec4(0.95f, 0.75f, 0.10f, 1.0f), glm::vec4(0.25f, 0.70f, 0.35f, 1.0f),
                glm::vec4(0.60f, 0.45f, 0.30f, 1.0f), glm::vec4(0.35f, 0.50f, 0.80f, 1.0f),
                glm::vec4(0.55f, 0.40f, 0.30f, 1.0f)};
            const std::size_t i = std::min<std::size_t>(subclass, kIcons.size() - 1);
            l.font = FontStyle::Regular;
            l.size_px = 15.0f;
            l.style = baseStyle(glm::vec4(1.0f, 0.96f, 0.88f, 1.0f));
            l.style.icon = kColors[i];
            l.icon = kIcons[i];
            break;
        }
        case map::LabelKind::Road:
            // Line labels: smaller, regular weight, pale yellow like the major road fill.
            l.font = FontStyle::Regular;
            l.size_px = subclass <= 2 ? 17.0f : 15.0f;
            l.style = baseStyle(glm::vec4(1.0f, 0.98f, 0.80f, 1.0f));
            break;
        case map::LabelKind::Area:
            // Water in blue tones, other areas in a pale green; thinner outline.
            l.font = FontStyle::Regular;
            l.size_px = 15.0f;
            l.world_reach = 4.0f;
            l.style = baseStyle(subclass == static_cast<std::uint8_t>(map::AreaClass::Water)
                                    ? glm::vec4(0.75f, 0.88f, 1.0f, 1.0f)
                                    : glm::vec4(0.86f, 0.95f, 0.84f, 1.0f));
            l.style.outline_px = 1.0f;
            break;
    }
    return l;
}

}  // namespace navmap::render::text
