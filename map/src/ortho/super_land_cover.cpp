// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/super_land_cover.h"

namespace navmap::map::ortho {

const char* superLandCoverName(SuperLandCover c) {
    using S = SuperLandCover;
    switch (c) {
        case S::Ocean: return "ocean";
        case S::Land: return "land";
        case S::Lake: return "lake";
        case S::Glacier: return "glacier";
        case S::IceShelf: return "ice shelf";
        case S::Urban: return "urban";
        case S::Playa: return "playa";
        case S::Wetland: return "wetland";
        case S::Forest: return "forest";
        case S::Scrub: return "scrub";
        case S::Grass: return "grass";
        case S::Farmland: return "farmland";
        case S::Rock: return "rock";
        case S::Residential: return "residential";
        case S::Commercial: return "commercial";
        case S::Industrial: return "industrial";
        case S::Park: return "park";
        case S::Sport: return "sport";
        case S::Cemetery: return "cemetery";
        case S::Military: return "military";
        case S::OtherArea: return "other area";
    }
    return "?";
}

SuperLandCover fromGlobal(GlobalCover c) { return static_cast<SuperLandCover>(c); }

SuperLandCover fromArea(AreaClass c) {
    using A = AreaClass;
    using S = SuperLandCover;
    switch (c) {
        case A::Sea: return S::Ocean;
        case A::Water: return S::Lake;
        case A::Glacier: return S::Glacier;
        case A::Wetland: return S::Wetland;
        case A::Forest: return S::Forest;
        case A::Scrub: return S::Scrub;
        case A::Grass: return S::Grass;
        case A::Farmland: return S::Farmland;
        case A::Rock: return S::Rock;
        case A::Residential: return S::Residential;
        case A::Commercial: return S::Commercial;
        case A::Industrial: return S::Industrial;
        case A::Park: return S::Park;
        case A::Sport: return S::Sport;
        case A::Cemetery: return S::Cemetery;
        case A::Military: return S::Military;
        case A::Other: return S::OtherArea;
        case A::Pier: return S::Industrial;    // concrete and stone over the water
        case A::Harbour: return S::OtherArea;  // a tint: rasterizeAreas leaves it out
    }
    return S::OtherArea;
}

GlobalCover trainedAs(SuperLandCover c) {
    using S = SuperLandCover;
    if (static_cast<int>(c) < kGlobalCoverCount) return static_cast<GlobalCover>(c);
    switch (c) {
        case S::Residential:
        case S::Commercial:
        case S::Industrial: return GlobalCover::Urban;
        default: return GlobalCover::Land;
    }
}

}  // namespace navmap::map::ortho
