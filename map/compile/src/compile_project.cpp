// SPDX-License-Identifier: Apache-2.0
// The project stage of compileStore (compile_stages.h): raw features into the store frame, with
// the labels they carry and the level-of-detail rules that say at which levels they appear.
#include <algorithm>
#include <cmath>

#include "compile_stages.h"

namespace navmap::map::detail {

namespace {

void orient(std::vector<PlanarPoint>& ring, bool ccw) {
    if ((ringSignedArea(ring) > 0) != ccw) std::reverse(ring.begin(), ring.end());
}

bool counted(const std::vector<char>& flags, std::size_t i) { return flags.empty() || flags[i] != 0; }

/// A projected road and whether it counts in the stats of this pass.
struct CountedRoad {
    PRoad road;
    bool counted;
};

/// The roads, by class (stable: input order within a class).
std::vector<CountedRoad> projectRoads(const RawFeatures& raw, const Projection& proj, CompileStats& stats) {
    std::vector<CountedRoad> roads;
    roads.reserve(raw.roads.size());
    for (std::size_t i = 0; i < raw.roads.size(); ++i) {
        const auto& r = raw.roads[i];
        PRoad p{&r, project(proj, r.points), {}};
        p.bounds = boundsOf(p.pts);
        const bool count = counted(raw.roads_counted, i);
        if (count) {
            stats.road_vertices += r.points.size();
            ++stats.roads;
        }
        roads.push_back({std::move(p), count});
    }
    std::stable_sort(roads.begin(), roads.end(),
                     [](const CountedRoad& a, const CountedRoad& b) { return a.road.raw->cls < b.road.raw->cls; });
    return roads;
}

/// The buildings that triangulate.
std::vector<PBuilding> projectBuildings(const RawFeatures& raw, const Projection& proj, CompileStats& stats) {
    std::vector<PBuilding> out;
    for (std::size_t i = 0; i < raw.buildings.size(); ++i) {
        const auto& b = raw.buildings[i];
        PBuilding pb;
        pb.poly = projectPolygon(proj, b.polygon);
        if (pb.poly.outers.empty()) continue;
        std::vector<std::vector<PlanarPoint>> rings = pb.poly.outers;
        rings.insert(rings.end(), pb.poly.inners.begin(), pb.poly.inners.end());
        pb.tri = triangulate(rings);
        if (!pb.tri.ok || pb.tri.indices.empty()) continue;
        std::uint32_t end = 0;
        for (const auto& r : rings) pb.ring_ends.push_back(end += static_cast<std::uint32_t>(r.size()));
        pb.height = b.height_m;
        pb.min_height = b.min_height_m;
        out.push_back(std::move(pb));
        if (counted(raw.buildings_counted, i)) ++stats.buildings;
    }
    return out;
}

/// The areas of positive area; a named one gets a label at its barycenter.
void projectAreas(const RawFeatures& raw, const Projection& proj, ProjectedFeatures& out, CompileStats& stats) {
    for (std::size_t i = 0; i < raw.areas.size(); ++i) {
        const auto& a = raw.areas[i];
        PArea pa{projectPolygon(proj, a.polygon), a.cls, &a.name};
        if (pa.poly.outers.empty() || pa.poly.area <= 0) continue;
        const bool count = counted(raw.areas_counted, i);
        if (!a.name.empty()) {
            const PlanarPoint ctr = pa.poly.barycenter;  // seed 4.4.2: area labels at the barycenter
            out.labels.push_back({LabelKind::Area, static_cast<std::uint8_t>(a.cls), &a.name, ctr, ctr, ctr,
                                  static_cast<float>(std::clamp(0.2 + 0.05 * std::log10(pa.poly.area + 1.0), 0.2, 0.5)),
                                  a.polygon.id, 0, pa.poly.area});
            if (count) ++stats.area_labels;
        }
        out.areas.push_back(std::move(pa));
        if (count) ++stats.areas;
    }
}

/// Point labels, then place labels at the barycenter of their polygons.
void projectPointLabels(const RawFeatures& raw, const Projection& proj, std::vector<PLabel>& labels,
                        CompileStats& stats) {
    for (std::size_t i = 0; i < raw.points.size(); ++i) {
        const auto& l = raw.points[i];
        const PlanarPoint p = proj.forward(l.pos.lat_deg, l.pos.lon_deg);
        labels.push_back({l.kind, l.subclass, &l.name, p, p, p, l.importance, l.id, pointLabelMaxTile(l), 0});
        if (counted(raw.points_counted, i)) (l.kind == LabelKind::Place ? stats.place_labels : stats.poi_labels)++;
    }
    for (std::size_t i = 0; i < raw.places.size(); ++i) {
        const auto& l = raw.places[i];
        const PPoly poly = projectPolygon(proj, l.polygon);
        if (poly.outers.empty()) continue;
        const PlanarPoint ctr = poly.barycenter;
        labels.push_back({LabelKind::Place, l.subclass, &l.name, ctr, ctr, ctr, l.importance, l.polygon.id,
                          placeMaxTile(static_cast<PlaceClass>(l.subclass)), 0});
        if (counted(raw.places_counted, i)) ++stats.place_labels;
    }
}

/// The roads' labels (named or numbered roads not in tunnels), and the roads.
void labelRoads(std::vector<CountedRoad> roads, ProjectedFeatures& out, CompileStats& stats) {
    out.roads.reserve(roads.size());
    for (auto& cr : roads) {
        const PRoad& r = cr.road;
        const std::string& name = r.raw->name.empty() ? r.raw->ref : r.raw->name;
        // Tunnels are not drawn on the surface (docs/rendering.md "Tunnels"), so not labelled there.
        if (!name.empty() && !(r.raw->flags & road_flags::kTunnel)) {
            // seed 4.4.2: polyline center for horizontal labels, longest straight segment for rotated ones.
            const Segment s = longestStraightSegment(r.pts);
            out.labels.push_back({LabelKind::Road, static_cast<std::uint8_t>(r.raw->cls), &name, polylineCenter(r.pts),
                                  s.a, s.b, 0.7f - 0.05f * static_cast<float>(r.raw->cls), r.raw->id,
                                  roadMaxTile(r.raw->cls), 0});
            if (cr.counted) ++stats.road_labels;
        }
        out.roads.push_back(std::move(cr.road));
    }
}

}  // namespace

double roadMaxTile(RoadClass c) {
    switch (c) {
        case RoadClass::Motorway:
        case RoadClass::Trunk: return kAlways;
        case RoadClass::Primary: return 64000;
        case RoadClass::Secondary: return 32000;
        case RoadClass::Tertiary: return 16000;
        case RoadClass::Unclassified:
        case RoadClass::Residential: return 8000;
        case RoadClass::Service:
        case RoadClass::Pedestrian: return 4000;
        default: return 0;  // tracks and paths: leaf only
    }
}

double placeMaxTile(PlaceClass c) {
    switch (c) {
        case PlaceClass::Country:
        case PlaceClass::State:
        case PlaceClass::City: return kAlways;
        case PlaceClass::Town: return 64000;
        case PlaceClass::Village: return 16000;
        case PlaceClass::Suburb: return 8000;
        case PlaceClass::Hamlet:
        case PlaceClass::Neighbourhood:
        case PlaceClass::Island: return 4000;
        default: return 0;
    }
}

double pointLabelMaxTile(const RawPointLabel& l) {
    return l.kind == LabelKind::Place ? placeMaxTile(static_cast<PlaceClass>(l.subclass))
                                      : (static_cast<PoiClass>(l.subclass) == PoiClass::Peak ? 16000.0 : 0.0);
}

std::vector<PlanarPoint> project(const Projection& proj, const std::vector<GeoCoordinate>& pts) {
    std::vector<PlanarPoint> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(proj.forward(p.lat_deg, p.lon_deg));
    return out;
}

PPoly projectPolygon(const Projection& proj, const RawPolygon& raw) {
    PPoly p;
    p.id = raw.id;
    for (const auto& r : raw.outers) {
        auto ring = project(proj, r);
        if (ring.size() < 3) continue;
        orient(ring, true);
        p.area += std::abs(ringSignedArea(ring));
        p.outers.push_back(std::move(ring));
    }
    for (const auto& r : raw.inners) {
        auto ring = project(proj, r);
        if (ring.size() < 3) continue;
        orient(ring, false);
        p.area -= std::abs(ringSignedArea(ring));
        p.inners.push_back(std::move(ring));
    }
    std::vector<PlanarPoint> all;
    for (const auto& r : p.outers) all.insert(all.end(), r.begin(), r.end());
    p.bounds = boundsOf(all);
    p.barycenter = polygonBarycenter(p.outers, p.inners);
    return p;
}

ProjectedFeatures projectFeatures(const RawFeatures& raw, const Projection& proj, const PArea* sea,
                                  CompileStats& stats) {
    ProjectedFeatures out;
    out.sea = sea;
    std::vector<CountedRoad> roads = projectRoads(raw, proj, stats);
    out.buildings = projectBuildings(raw, proj, stats);
    projectAreas(raw, proj, out, stats);
    projectPointLabels(raw, proj, out.labels, stats);
    labelRoads(std::move(roads), out, stats);
    return out;
}

}  // namespace navmap::map::detail
