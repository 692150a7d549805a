// SPDX-License-Identifier: Apache-2.0
#pragma once
// The classes of areas, places and POIs as the tile store keeps them: plain data that the
// compiler writes (tag_rules.h turns OSM tags into them) and the renderer reads.

#include <cstdint>
#include <string_view>

namespace navmap::map {

/// Area classes: the Shortbread 1.0 vector-tile schema's area layers (ocean, water_polygons,
/// land, sites, pier_polygons) mapped onto the classes navmap draws. docs/tile-store.md ("Area
/// classes") has the whole table, OSM tags -> layer and kind -> class; tag_rules.cpp implements it.
/// Stored as u8: values are only ever appended, so a store keeps its meaning in later builds.
enum class AreaClass : std::uint8_t {
    Water = 0,  ///< water_polygons: water, river, reservoir, basin, dock, lock, harbour
    Wetland,    ///< land: wetland (swamp, bog, marsh, wet_meadow, ...)
    Glacier,    ///< water_polygons: glacier
    Forest,     ///< land: forest (landuse=forest, natural=wood)
    Scrub,      ///< land: scrub, heath
    Grass,      ///< land: grass, meadow, grassland, village_green, greenfield
    Farmland,   ///< land: farmland, farmyard, orchard, vineyard, allotments, plant_nursery
    Rock,       ///< land: bare_rock, scree, shingle, sand, beach
    Residential,
    Commercial,  ///< land: commercial, retail
    Industrial,  ///< land: industrial, railway, quarry, landfill, brownfield, garages; sites: construction
    Park,        ///< land: park, garden, dog_park, recreation_ground
    Sport,       ///< land: golf_course, playground; pitch, sports_centre, stadium, track (navmap)
    Cemetery,    ///< land: cemetery, grave_yard
    Military,    ///< sites: military
    Other,       ///< no longer written (stores compiled before the schema: any other landuse/natural)
    Sea,         ///< ocean: assembled from natural=coastline ways (coastline.h); never from tags
    Pier,        ///< pier_polygons: pier, breakwater, groyne; drawn over the water
    Harbour,     ///< leisure=marina, landuse=harbour/port (navmap): a translucent tint over water and land
};
inline constexpr int kAreaClassCount = 19;

/// Whether the class is a translucent tint that must not hide what lies under it (a harbour
/// over its basin): the orthoimage's land-cover raster leaves it out.
bool areaIsTint(AreaClass cls);

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

/// Lowest first (the schema's order): the sea under everything mapped on land, then large
/// natural classes, built-up, parks and sports, wetland, water over all land cover, the harbour
/// tint over the water, and piers and breakwaters last, over the water and the tint. The
/// terrain's land-cover texture and the orthoimage's super land cover both paint in this order.
int areaDrawOrder(AreaClass cls);

}  // namespace navmap::map
