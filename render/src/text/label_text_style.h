// SPDX-License-Identifier: Apache-2.0
#pragma once
// Text appearance per label kind: places sized by class, POIs with an icon, road names as
// line labels, area names (issue 4; seed 4.5.2 for the outline and halo).

#include <cstdint>
#include <string>

#include "navmap/map/tile.h"
#include "navmap/render/text/font_collection.h"
#include "text_draw.h"

namespace navmap::render::text {

struct LabelTextStyle {
    FontStyle font = FontStyle::Regular;
    float size_px = 14.0f;  ///< em size at scale 1
    TextStyle style;
    /// POIs: the symbol drawn left of the name (a DejaVu Sans glyph, UTF-8); empty otherwise.
    std::string icon;
    /// World-space text (snail's view, seed 5.2.1) has a fixed size in the world: `size_px` at
    /// `world_reach` times the camera's look-at distance, so it is readable (cap height >= 10 px)
    /// out to about that far and fades out beyond. A street name is read near the car (the
    /// snail's view's 180 m look-at distance: out to about 600 m), a town's from afar.
    float world_reach = 3.0f;
};

/// Style of a tile label: `kind` and `subclass` as in map::Label (PlaceClass, PoiClass,
/// RoadClass or AreaClass). Unknown subclasses get the kind's smallest style.
LabelTextStyle labelTextStyle(map::LabelKind kind, std::uint8_t subclass);

}  // namespace navmap::render::text
