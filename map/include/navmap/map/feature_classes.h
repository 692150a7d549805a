// SPDX-License-Identifier: Apache-2.0
#pragma once
// The classes of areas, places and POIs as the tile store keeps them: plain data that the
// compiler writes (tag_rules.h turns OSM tags into them) and the renderer reads.

#include <cstdint>
#include <string_view>

namespace navmap::map {

/// Land-cover / area classes (seed 2.1.2 thematic layers).
enum class AreaClass : std::uint8_t {
    Water = 0,  ///< natural=water, waterway=riverbank, landuse=reservoir/basin
    Wetland,
    Glacier,
    Forest,    ///< landuse=forest, natural=wood
    Scrub,     ///< natural=scrub/heath
    Grass,     ///< landuse=grass/meadow/village_green, natural=grassland
    Farmland,  ///< landuse=farmland/farmyard/orchard/vineyard/allotments
    Rock,      ///< natural=bare_rock/scree/shingle/sand/beach
    Residential,
    Commercial,  ///< landuse=commercial/retail
    Industrial,  ///< landuse=industrial/railway/quarry/landfill/construction/brownfield
    Park,        ///< leisure=park/garden/nature_reserve, landuse=recreation_ground
    Sport,       ///< leisure=pitch/sports_centre/stadium/golf_course/track/playground, landuse=winter_sports
    Cemetery,
    Military,
    Other,  ///< any other landuse/natural/leisure value
    Sea,    ///< the sea, assembled from natural=coastline ways (coastline.h); never from tags
};
inline constexpr int kAreaClassCount = 17;

/// place=* classes, largest first.
enum class PlaceClass : std::uint8_t {
    Country = 0,
    State,
    City,
    Town,
    Village,
    Suburb,
    Hamlet,
    Neighbourhood,
    Locality,
    IsolatedDwelling,
    Island,
    Other,
};

/// Kinds of named POI nodes.
enum class PoiClass : std::uint8_t { Amenity = 0, Shop, Tourism, Leisure, Historic, Office, Peak };

/// Importance in [0, 1] used as label priority (seed 4.4.3 places labels by priority).
float placeImportance(PlaceClass cls);

std::string_view areaClassName(AreaClass cls);
std::string_view placeClassName(PlaceClass cls);

/// Lowest first: the sea under everything mapped on land (harbours, piers, beaches), then large
/// natural classes, built-up, parks and sports, wetland, and water last so rivers stay visible.
/// The terrain's land-cover texture and the orthoimage's super land cover both paint in this
/// order.
int areaDrawOrder(AreaClass cls);

}  // namespace navmap::map
