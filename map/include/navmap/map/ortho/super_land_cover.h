// SPDX-License-Identifier: Apache-2.0
#pragma once
// The super land cover (seed 6.5 "Land cover unification"): every category of the land-cover
// sources in one set, redundant ones merged. The sources here are Natural Earth 1:50m (global,
// GlobalCover) and the region's OpenStreetMap areas (AreaClass, tile resolution). OSM water and
// glaciers merge into the Natural Earth lake and glacier classes; OSM's finer classes stay their
// own. Only the Natural Earth classes exist worldwide, so only they can be trained against Blue
// Marble: an OSM class feeds the network the node of the global class it refines (trainedAs) and
// selects the procedural detail drawn over the network's colour (seed 6.7).

#include <cstdint>

#include "navmap/map/feature_classes.h"
#include "navmap/map/ortho/natural_earth.h"
#include "navmap/map/ortho/ortho_layers.h"

namespace navmap::map::ortho {

enum class SuperLandCover : std::uint8_t {
    // Natural Earth 1:50m (GlobalCover order).
    Ocean = 0,
    Land,
    Lake,
    Glacier,
    IceShelf,
    Urban,
    Playa,
    // OpenStreetMap areas (AreaClass without water and glacier).
    Wetland,
    Forest,
    Scrub,
    Grass,
    Farmland,
    Rock,
    Residential,
    Commercial,
    Industrial,
    Park,
    Sport,
    Cemetery,
    Military,
    OtherArea,
};
inline constexpr int kSuperLandCoverCount = 21;
static_assert(kSuperLandCoverCount == kCoverCodeCount, "the stored layer codes (ortho_layers.h)");

const char* superLandCoverName(SuperLandCover c);
SuperLandCover fromGlobal(GlobalCover c);
SuperLandCover fromArea(AreaClass c);
/// The trained network input (global class) a super class activates.
GlobalCover trainedAs(SuperLandCover c);

/// Procedural detail per class (seed 6.7).
inline bool isVegetation(SuperLandCover c) { return c == SuperLandCover::Forest || c == SuperLandCover::Scrub; }
inline bool isFarmland(SuperLandCover c) { return c == SuperLandCover::Farmland; }

}  // namespace navmap::map::ortho
