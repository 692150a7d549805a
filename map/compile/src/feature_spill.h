// SPDX-License-Identifier: Apache-2.0
#pragma once
// The raw features of navmap-compile (osm_handlers.h) as spill records (spill_file.h): what
// the bounded-memory compile writes while it reads the OSM file and reads back one tile band
// at a time. A record is a tag byte (FeatureTag, with kRepeatFlag set where the feature was
// already given to an earlier band) and the feature, little-endian, coordinates as IEEE doubles
// so that a round trip is exact. Private to navmap_map.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "osm_handlers.h"

namespace navmap::map::detail {

enum class FeatureTag : std::uint8_t { Road = 1, Building, Area, PointLabel, PlaceLabel, GraphWay };
inline constexpr std::uint8_t kRepeatFlag = 0x80;

/// The features of a whole input or of one band, in input order per kind. `*_counted` say per
/// feature whether it counts in CompileStats here (false: an earlier band counted it); empty
/// means all count.
struct RawFeatures {
    std::vector<RawRoad> roads;
    std::vector<RawBuilding> buildings;
    std::vector<RawArea> areas;
    std::vector<RawPointLabel> points;
    std::vector<RawAreaLabel> places;
    std::vector<RawGraphWay> graph_ways;
    std::vector<char> roads_counted, buildings_counted, areas_counted, points_counted, places_counted;
};

std::vector<std::uint8_t> encodeFeature(const RawRoad& f);
std::vector<std::uint8_t> encodeFeature(const RawBuilding& f);
std::vector<std::uint8_t> encodeFeature(const RawArea& f);
std::vector<std::uint8_t> encodeFeature(const RawPointLabel& f);
std::vector<std::uint8_t> encodeFeature(const RawAreaLabel& f);
std::vector<std::uint8_t> encodeFeature(const RawGraphWay& f);

/// Appends the record's feature to the matching vector of `out` (and its counted flag); false
/// with `error` ("unknown feature tag 9", "truncated varint at byte 17", ...) otherwise.
bool decodeFeature(std::span<const std::uint8_t> record, RawFeatures& out, std::string& error);

}  // namespace navmap::map::detail
