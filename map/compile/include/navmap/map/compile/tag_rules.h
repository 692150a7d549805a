// SPDX-License-Identifier: Apache-2.0
#pragma once
// OSM tag interpretation for the compiler: building heights, speeds, one-way rules and the
// classes of areas, places and POIs (feature_classes.h). Pure functions over a tag lookup, so
// they are testable without libosmium objects. Offline only: navmapd reads the classes from
// the store and never interprets tags.

#include <array>
#include <functional>
#include <optional>
#include <string_view>

#include "navmap/map/feature_classes.h"

namespace navmap::map {

/// Returns the value of a tag or nullptr when the object does not have it.
using TagLookup = std::function<const char*(const char* key)>;

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

/// The keys an area (closed way or multipolygon relation) needs one of to be assembled at all:
/// buildings, place polygons and everything areaClassFromTags may classify.
inline constexpr std::array<const char*, 8> kAreaTagKeys{"building", "landuse", "natural",  "leisure",
                                                         "waterway", "amenity", "man_made", "place"};

/// The area class of a closed way or multipolygon by the Shortbread 1.0 schema's area layers
/// (docs/tile-store.md, "Area classes"), or nullopt when the schema draws it as no area:
/// boundaries (type=boundary, boundary=*), place polygons, bays, straits, mountain ranges and any
/// tag the schema does not classify. Multipolygons keep their relation's type tag for this.
std::optional<AreaClass> areaClassFromTags(const TagLookup& tags);
/// The place class under which a named polygon is labelled: its place=*, or a locality for a
/// named natural=bay, strait, peninsula, cape, mountain_range or valley; nullopt otherwise.
std::optional<PlaceClass> areaLabelClassFromTags(const TagLookup& tags);
std::optional<PlaceClass> placeClassFromTag(std::string_view place);
/// POI class for named point features, or nullopt.
std::optional<PoiClass> poiClassFromTags(const TagLookup& tags);

}  // namespace navmap::map
