// SPDX-License-Identifier: Apache-2.0
#pragma once
// The small single-purpose libosmium handlers of navmap-compile (one class each, as in
// libosmium's own examples). They only collect raw features in WGS84; projection and tiling
// happen afterwards (compile_stages.h). Private to navmap_map_compile.

#include <osmium/handler.hpp>
#include <osmium/osm/area.hpp>
#include <osmium/osm/node.hpp>
#include <osmium/osm/way.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/common/geo_coordinate.h"
#include "navmap/map/compile/speed_limit_tags.h"
#include "navmap/map/compile/tag_rules.h"
#include "navmap/map/compile/turn_lane_tags.h"
#include "navmap/map/road_class.h"
#include "navmap/map/tile.h"

namespace navmap::map::detail {

struct RawRoad {
    std::int64_t id = 0;
    RoadClass cls = RoadClass::Path;
    std::uint8_t flags = 0;
    std::int8_t layer = 0;
    std::uint16_t maxspeed = 0;
    std::string name, ref;
    std::vector<GeoCoordinate> points;  ///< in travel direction for one-way roads
};

struct RawGraphWay {
    std::int64_t id = 0;
    RoadClass cls = RoadClass::Path;
    std::uint8_t flags = 0;
    float speed_kmh = 0;
    /// The legal limit along and against `nodes` (their order after a oneway=-1 reversal),
    /// km/h, 0 unknown (speed_limit_tags.h).
    std::uint16_t limit_forward_kmh = 0;
    std::uint16_t limit_backward_kmh = 0;
    /// The turn lanes along and against `nodes` (as kept), lane_arrow bits left to right in the
    /// direction of travel; empty: none (turn_lane_tags.h).
    std::vector<std::uint16_t> lanes_forward, lanes_backward;
    bool oneway = false;
    std::vector<std::int64_t> nodes;
    std::vector<GeoCoordinate> points;
};

struct RawPolygon {
    std::int64_t id = 0;
    std::vector<std::vector<GeoCoordinate>> outers, inners;
};

/// A natural=coastline way, or one run of it where a cut extract lacks some node locations.
struct RawCoastWay {
    std::int64_t id = 0;
    std::int64_t first_node = 0, last_node = 0;
    std::vector<GeoCoordinate> points;
};

struct RawBuilding {
    RawPolygon polygon;
    float height_m = 0, min_height_m = 0;
};

struct RawArea {
    RawPolygon polygon;
    AreaClass cls = AreaClass::Other;
    std::string name;
};

struct RawPointLabel {
    LabelKind kind = LabelKind::Place;
    std::uint8_t subclass = 0;
    std::string name;
    GeoCoordinate pos;
    float importance = 0;
    std::int64_t id = 0;
};

struct RawAreaLabel {  ///< named place polygons (place=* on ways/relations), anchored at the barycenter
    RawPolygon polygon;
    std::uint8_t subclass = 0;
    std::string name;
    float importance = 0;
};

/// highway=* ways -> road polylines with class, name, ref, oneway, layer, bridge, tunnel, maxspeed.
class RoadHandler : public osmium::handler::Handler {
public:
    void way(const osmium::Way& way);
    std::vector<RawRoad> roads;
    std::size_t vertices = 0;
};

/// highway=* ways -> node-id sequences for the routing graph.
class GraphHandler : public osmium::handler::Handler {
public:
    void way(const osmium::Way& way);
    std::vector<RawGraphWay> ways;
    /// Turn lanes read (turn_lane_tags.h): ways with some, values ignored, tags not used.
    std::size_t turn_lane_ways = 0, turn_lane_values_ignored = 0, turn_lane_tags_dropped = 0;
};

/// building=* areas (closed ways and multipolygons) -> footprints with heights.
class BuildingHandler : public osmium::handler::Handler {
public:
    explicit BuildingHandler(float default_height) : m_default_height(default_height) {}
    void area(const osmium::Area& area);
    std::vector<RawBuilding> buildings;

private:
    float m_default_height;
};

/// landuse/natural/water/leisure areas -> land-cover polygons.
class AreaHandler : public osmium::handler::Handler {
public:
    void area(const osmium::Area& area);
    std::vector<RawArea> areas;
};

/// natural=coastline ways -> runs of located nodes (the land/sea split, coastline.h).
class CoastlineHandler : public osmium::handler::Handler {
public:
    void way(const osmium::Way& way);
    std::vector<RawCoastWay> ways;
};

/// place nodes and named POI nodes -> point labels; place polygons -> area-anchored place labels.
class LabelHandler : public osmium::handler::Handler {
public:
    void node(const osmium::Node& node);
    void area(const osmium::Area& area);
    std::vector<RawPointLabel> points;
    std::vector<RawAreaLabel> places;
};

}  // namespace navmap::map::detail
