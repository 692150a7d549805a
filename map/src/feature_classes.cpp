// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/feature_classes.h"

#include <array>
#include <cstddef>

namespace navmap::map {

float placeImportance(PlaceClass cls) {
    static constexpr std::array<float, 12> kImportance{1.0f, 0.95f, 0.9f, 0.8f,  0.6f, 0.5f,
                                                       0.4f, 0.3f,  0.2f, 0.15f, 0.3f, 0.1f};
    return kImportance[static_cast<std::size_t>(cls)];
}

int areaDrawOrder(AreaClass cls) {
    using A = AreaClass;
    switch (cls) {
        case A::Sea: return -1;
        case A::Forest:
        case A::Scrub:
        case A::Grass:
        case A::Farmland:
        case A::Rock:
        case A::Glacier: return 0;
        case A::Residential:
        case A::Commercial:
        case A::Industrial:
        case A::Military:
        case A::Cemetery: return 1;
        case A::Park:
        case A::Sport:
        case A::Other: return 2;
        case A::Wetland: return 3;
        case A::Water: return 4;
        case A::Harbour: return 5;
        case A::Pier: return 6;
    }
    return 2;
}

bool areaIsTint(AreaClass cls) { return cls == AreaClass::Harbour; }

std::string_view areaClassName(AreaClass cls) {
    static constexpr std::array<std::string_view, kAreaClassCount> kNames{
        "water",    "wetland",     "glacier",    "forest",     "scrub",  "grass", "farmland",
        "rock",     "residential", "commercial", "industrial", "park",   "sport", "cemetery",
        "military", "other",       "sea",        "pier",       "harbour"};
    return kNames[static_cast<std::size_t>(cls)];
}

std::string_view placeClassName(PlaceClass cls) {
    static constexpr std::array<std::string_view, 12> kNames{
        "country",           "state",  "city", "town", "village", "suburb", "hamlet", "neighbourhood", "locality",
        "isolated_dwelling", "island", "other"};
    return kNames[static_cast<std::size_t>(cls)];
}

}  // namespace navmap::map
