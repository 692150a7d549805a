// SPDX-License-Identifier: Apache-2.0
#include "osm_handlers.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace navmap::map::detail {

namespace {

TagLookup lookup(const osmium::TagList& tags) {
    return [&tags](const char* key) { return tags[key]; };
}

std::string tagOr(const osmium::TagList& tags, const char* key) {
    const char* v = tags[key];
    return v ? std::string(v) : std::string();
}

/// Locations of a node list; false when a location is missing (node outside the extract).
bool locations(const osmium::NodeRefList& nodes, std::vector<GeoCoordinate>& out) {
    out.clear();
    out.reserve(nodes.size());
    for (const auto& n : nodes) {
        const osmium::Location l = n.location();
        if (!l.valid()) return false;
        const GeoCoordinate p{l.lat(), l.lon()};
        if (!out.empty() && out.back() == p) continue;
        out.push_back(p);
    }
    return true;
}

bool polygonOf(const osmium::Area& area, RawPolygon& poly) {
    poly.id = area.orig_id();
    std::vector<GeoCoordinate> ring;
    for (const auto& outer : area.outer_rings()) {
        if (!locations(outer, ring) || ring.size() < 4) continue;
        ring.pop_back();  // closed ring: drop the repeated first point
        poly.outers.push_back(ring);
        for (const auto& inner : area.inner_rings(outer)) {
            if (!locations(inner, ring) || ring.size() < 4) continue;
            ring.pop_back();
            poly.inners.push_back(ring);
        }
    }
    return !poly.outers.empty();
}

}  // namespace

void RoadHandler::way(const osmium::Way& way) {
    const auto& tags = way.tags();
    const char* hw = tags["highway"];
    if (hw == nullptr || way.nodes().size() < 2) return;
    const auto mapping = roadClassFromHighway(hw);
    if (!mapping || tags.has_tag("area", "yes")) return;
    RawRoad road;
    if (!locations(way.nodes(), road.points) || road.points.size() < 2) return;
    road.id = way.id();
    road.cls = mapping->cls;
    const auto get = lookup(tags);
    const int dir = onewayDirection(get);
    if (dir != 0) road.flags |= road_flags::kOneway;
    if (dir < 0) std::reverse(road.points.begin(), road.points.end());
    if (mapping->link) road.flags |= road_flags::kLink;
    if (tags["bridge"] && !tags.has_tag("bridge", "no")) road.flags |= road_flags::kBridge;
    if (tags["tunnel"] && !tags.has_tag("tunnel", "no")) road.flags |= road_flags::kTunnel;
    if (tags.has_tag("junction", "roundabout")) road.flags |= road_flags::kRoundabout;
    if (const char* layer = tags["layer"]) road.layer = static_cast<std::int8_t>(std::clamp(std::atoi(layer), -5, 5));
    if (const char* ms = tags["maxspeed"]) {
        if (auto v = parseMaxspeedKmh(ms)) road.maxspeed = static_cast<std::uint16_t>(std::lround(*v));
    }
    road.name = tagOr(tags, "name");
    road.ref = tagOr(tags, "ref");
    vertices += road.points.size();
    roads.push_back(std::move(road));
}

void CoastlineHandler::way(const osmium::Way& way) {
    if (!way.tags().has_tag("natural", "coastline")) return;
    RawCoastWay run;
    auto flush = [&] {
        if (run.points.size() >= 2) ways.push_back(run);
        run.points.clear();
    };
    for (const auto& n : way.nodes()) {
        const osmium::Location l = n.location();
        if (!l.valid()) {  // outside a cut extract: the run ends here
            flush();
            continue;
        }
        if (run.points.empty()) {
            run.id = way.id();
            run.first_node = n.ref();
        }
        run.last_node = n.ref();
        const GeoCoordinate p{l.lat(), l.lon()};
        if (run.points.empty() || run.points.back() != p) run.points.push_back(p);
    }
    flush();
}

void GraphHandler::way(const osmium::Way& way) {
    const auto& tags = way.tags();
    const char* hw = tags["highway"];
    if (hw == nullptr || way.nodes().size() < 2) return;
    const auto mapping = roadClassFromHighway(hw);
    if (!mapping || tags.has_tag("area", "yes")) return;
    RawGraphWay g;
    g.id = way.id();
    g.cls = mapping->cls;
    for (const auto& n : way.nodes()) {
        if (!n.location().valid()) return;
        if (!g.nodes.empty() && g.nodes.back() == n.ref()) continue;
        g.nodes.push_back(n.ref());
        g.points.push_back({n.location().lat(), n.location().lon()});
    }
    if (g.nodes.size() < 2) return;
    const int dir = onewayDirection(lookup(tags));
    const DirectionalSpeedLimits limits = speedLimitsFromTags(lookup(tags));
    g.limit_forward_kmh = limits.forward_kmh;
    g.limit_backward_kmh = limits.backward_kmh;
    DirectionalTurnLanes lanes = turnLanesFromTags(lookup(tags), dir);
    turn_lane_values_ignored += lanes.unknown_values;
    turn_lane_tags_dropped += lanes.dropped;
    if (!lanes.forward.empty() || !lanes.backward.empty()) ++turn_lane_ways;
    g.lanes_forward = std::move(lanes.forward);
    g.lanes_backward = std::move(lanes.backward);
    if (dir < 0) {
        std::reverse(g.nodes.begin(), g.nodes.end());
        std::reverse(g.points.begin(), g.points.end());
        // "forward" follows the nodes as kept
        std::swap(g.limit_forward_kmh, g.limit_backward_kmh);
        std::swap(g.lanes_forward, g.lanes_backward);
    }
    g.oneway = dir != 0;
    if (g.oneway) g.flags |= road_flags::kOneway;
    if (mapping->link) g.flags |= road_flags::kLink;
    if (tags["bridge"] && !tags.has_tag("bridge", "no")) g.flags |= road_flags::kBridge;
    if (tags["tunnel"] && !tags.has_tag("tunnel", "no")) g.flags |= road_flags::kTunnel;
    // Guidance announces a roundabout as one manoeuvre with its exit number (docs/guidance.md).
    if (tags.has_tag("junction", "roundabout") || tags.has_tag("junction", "circular"))
        g.flags |= road_flags::kRoundabout;
    g.speed_kmh = defaultSpeedKmh(g.cls);
    if (const char* ms = tags["maxspeed"]) {
        if (auto v = parseMaxspeedKmh(ms)) g.speed_kmh = *v;
    }
    ways.push_back(std::move(g));
}

void BuildingHandler::area(const osmium::Area& area) {
    const auto& tags = area.tags();
    const char* b = tags["building"];
    if (b == nullptr || std::string_view(b) == "no") return;
    RawBuilding building;
    if (!polygonOf(area, building.polygon)) return;
    const auto get = lookup(tags);
    building.height_m = buildingHeight(get, m_default_height);
    building.min_height_m = std::min(buildingMinHeight(get), building.height_m);
    buildings.push_back(std::move(building));
}

void AreaHandler::area(const osmium::Area& area) {
    const auto& tags = area.tags();
    if (tags["building"]) return;
    const auto cls = areaClassFromTags(lookup(tags));
    if (!cls) return;
    RawArea a;
    if (!polygonOf(area, a.polygon)) return;
    a.cls = *cls;
    a.name = tagOr(tags, "name");
    areas.push_back(std::move(a));
}

void LabelHandler::node(const osmium::Node& node) {
    const auto& tags = node.tags();
    const char* name = tags["name"];
    if (name == nullptr || !node.location().valid()) return;
    RawPointLabel l;
    l.name = name;
    l.pos = {node.location().lat(), node.location().lon()};
    l.id = node.id();
    if (const char* place = tags["place"]) {
        const auto cls = placeClassFromTag(place);
        if (!cls) return;
        l.kind = LabelKind::Place;
        l.subclass = static_cast<std::uint8_t>(*cls);
        l.importance = placeImportance(*cls);
    } else if (const auto poi = poiClassFromTags(lookup(tags))) {
        l.kind = LabelKind::Poi;
        l.subclass = static_cast<std::uint8_t>(*poi);
        l.importance = *poi == PoiClass::Peak ? 0.35f : 0.25f;
    } else {
        return;
    }
    points.push_back(std::move(l));
}

void LabelHandler::area(const osmium::Area& area) {
    const auto& tags = area.tags();
    const char* name = tags["name"];
    if (name == nullptr) return;
    const auto cls = areaLabelClassFromTags(lookup(tags));
    if (!cls) return;
    RawAreaLabel l;
    if (!polygonOf(area, l.polygon)) return;
    l.subclass = static_cast<std::uint8_t>(*cls);
    l.importance = placeImportance(*cls);
    l.name = name;
    places.push_back(std::move(l));
}

}  // namespace navmap::map::detail
