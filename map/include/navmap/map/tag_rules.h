// SPDX-License-Identifier: Apache-2.0
#pragma once
// OSM tag interpretation for the compiler: building heights, speeds, one-way rules and the
// classes of areas, places and POIs. Pure functions over a tag lookup, so they are testable
// without libosmium objects.

#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

namespace navmap::map {

/// Returns the value of a tag or nullptr when the object does not have it.
using TagLookup = std::function<const char*(const char* key)>;

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

/// Building height in metres: `height` (m, "12 m", "40 ft" and 10'6" understood), else
/// `building:levels` x 3 m (+ roof:levels x 3 m / 2), else `default_m`.
float buildingHeight(const TagLookup& tags, float default_m = 8.0f);
/// Height of the building's base: `min_height`, else `building:min_level` x 3 m, else 0.
float buildingMinHeight(const TagLookup& tags);

/// Parses an OSM length ("12", "12.5 m", "40 ft", "40'", "10'6\"") to metres.
std::optional<float> parseLength(std::string_view text);
/// Parses maxspeed ("50", "30 mph", "50 km/h"); nullopt for "none", "signals", zone codes.
std::optional<float> parseMaxspeedKmh(std::string_view text);

/// Direction of travel allowed: +1 forward only, -1 backward only, 0 both. oneway=yes/1/true,
/// -1/reverse; motorways and roundabouts are one-way unless oneway=no.
int onewayDirection(const TagLookup& tags);

/// The area class of a closed way or multipolygon, or nullopt when it is not a land-cover area.
std::optional<AreaClass> areaClassFromTags(const TagLookup& tags);
std::optional<PlaceClass> placeClassFromTag(std::string_view place);
/// POI class for named point features, or nullopt.
std::optional<PoiClass> poiClassFromTags(const TagLookup& tags);

/// Importance in [0, 1] used as label priority (seed 4.4.3 places labels by priority).
float placeImportance(PlaceClass cls);

std::string_view areaClassName(AreaClass cls);
std::string_view placeClassName(PlaceClass cls);

}  // namespace navmap::map
