// SPDX-License-Identifier: Apache-2.0
#include "feature_spill.h"

#include "byte_io.h"

namespace navmap::map::detail {

namespace {

// Rings and vertex counts above this are damage (a real way has at most 2000 nodes; multipolygon
// rings are longer, but not a billion points).
constexpr std::uint64_t kMaxCount = 1u << 28;

ByteWriter start(FeatureTag tag) {
    ByteWriter w;
    w.u8(static_cast<std::uint8_t>(tag));
    return w;
}

void putPoints(ByteWriter& w, const std::vector<GeoCoordinate>& pts) {
    w.varint(pts.size());
    for (const auto& p : pts) {
        w.f64(p.lat_deg);
        w.f64(p.lon_deg);
    }
}

void putRings(ByteWriter& w, const std::vector<std::vector<GeoCoordinate>>& rings) {
    w.varint(rings.size());
    for (const auto& r : rings) putPoints(w, r);
}

void putPolygon(ByteWriter& w, const RawPolygon& p) {
    w.i64(p.id);
    putRings(w, p.outers);
    putRings(w, p.inners);
}

std::size_t count(ByteReader& r, std::size_t bytes_each) {
    const std::uint64_t n = r.varint();
    if (n > kMaxCount || n * bytes_each > r.remaining()) {
        r.fail("count " + std::to_string(n) + " beyond the record");
        return 0;
    }
    return static_cast<std::size_t>(n);
}

std::vector<GeoCoordinate> getPoints(ByteReader& r) {
    std::vector<GeoCoordinate> pts(count(r, 16));
    for (auto& p : pts) {
        p.lat_deg = r.f64();
        p.lon_deg = r.f64();
    }
    return pts;
}

std::vector<std::vector<GeoCoordinate>> getRings(ByteReader& r) {
    std::vector<std::vector<GeoCoordinate>> rings(count(r, 1));
    for (auto& ring : rings) ring = getPoints(r);
    return rings;
}

RawPolygon getPolygon(ByteReader& r) {
    RawPolygon p;
    p.id = r.i64();
    p.outers = getRings(r);
    p.inners = getRings(r);
    return p;
}

std::string getString(ByteReader& r) {
    const std::size_t n = count(r, 1);
    std::string s(n, '\0');
    for (auto& c : s) c = static_cast<char>(r.u8());
    return s;
}

}  // namespace

std::vector<std::uint8_t> encodeFeature(const RawRoad& f) {
    ByteWriter w = start(FeatureTag::Road);
    w.i64(f.id);
    w.u8(static_cast<std::uint8_t>(f.cls));
    w.u8(f.flags);
    w.u8(static_cast<std::uint8_t>(f.layer));
    w.u16(f.maxspeed);
    w.str(f.name);
    w.str(f.ref);
    putPoints(w, f.points);
    return std::move(w.bytes());
}

std::vector<std::uint8_t> encodeFeature(const RawBuilding& f) {
    ByteWriter w = start(FeatureTag::Building);
    putPolygon(w, f.polygon);
    w.f32(f.height_m);
    w.f32(f.min_height_m);
    return std::move(w.bytes());
}

std::vector<std::uint8_t> encodeFeature(const RawArea& f) {
    ByteWriter w = start(FeatureTag::Area);
    putPolygon(w, f.polygon);
    w.u8(static_cast<std::uint8_t>(f.cls));
    w.str(f.name);
    return std::move(w.bytes());
}

std::vector<std::uint8_t> encodeFeature(const RawPointLabel& f) {
    ByteWriter w = start(FeatureTag::PointLabel);
    w.u8(static_cast<std::uint8_t>(f.kind));
    w.u8(f.subclass);
    w.str(f.name);
    w.f64(f.pos.lat_deg);
    w.f64(f.pos.lon_deg);
    w.f32(f.importance);
    w.i64(f.id);
    return std::move(w.bytes());
}

std::vector<std::uint8_t> encodeFeature(const RawAreaLabel& f) {
    ByteWriter w = start(FeatureTag::PlaceLabel);
    putPolygon(w, f.polygon);
    w.u8(f.subclass);
    w.str(f.name);
    w.f32(f.importance);
    return std::move(w.bytes());
}

std::vector<std::uint8_t> encodeFeature(const RawGraphWay& f) {
    ByteWriter w = start(FeatureTag::GraphWay);
    w.i64(f.id);
    w.u8(static_cast<std::uint8_t>(f.cls));
    w.u8(f.flags);
    w.f32(f.speed_kmh);
    w.u16(f.limit_forward_kmh);
    w.u16(f.limit_backward_kmh);
    for (const auto* lanes : {&f.lanes_forward, &f.lanes_backward}) {
        w.varint(lanes->size());
        for (const std::uint16_t a : *lanes) w.u16(a);
    }
    w.u8(f.oneway ? 1 : 0);
    w.varint(f.nodes.size());
    std::int64_t prev = 0;
    for (const auto n : f.nodes) {
        w.svarint(static_cast<std::int64_t>(static_cast<std::uint64_t>(n) - static_cast<std::uint64_t>(prev)));
        prev = n;
    }
    putPoints(w, f.points);
    return std::move(w.bytes());
}

bool decodeFeature(std::span<const std::uint8_t> record, RawFeatures& out, std::string& error) {
    ByteReader r(record);
    const std::uint8_t tag_byte = r.u8();
    if (r.failed()) {
        error = "empty record";
        return false;
    }
    const char counted = (tag_byte & kRepeatFlag) ? 0 : 1;
    const auto tag = static_cast<FeatureTag>(tag_byte & ~kRepeatFlag);
    // Decoded whole first, appended only when intact.
    switch (tag) {
        case FeatureTag::Road: {
            RawRoad f;
            f.id = r.i64();
            f.cls = static_cast<RoadClass>(r.u8());
            f.flags = r.u8();
            f.layer = static_cast<std::int8_t>(r.u8());
            f.maxspeed = r.u16();
            f.name = getString(r);
            f.ref = getString(r);
            f.points = getPoints(r);
            if (r.failed() || r.remaining() != 0) break;
            out.roads.push_back(std::move(f));
            out.roads_counted.push_back(counted);
            return true;
        }
        case FeatureTag::Building: {
            RawBuilding f;
            f.polygon = getPolygon(r);
            f.height_m = r.f32();
            f.min_height_m = r.f32();
            if (r.failed() || r.remaining() != 0) break;
            out.buildings.push_back(std::move(f));
            out.buildings_counted.push_back(counted);
            return true;
        }
        case FeatureTag::Area: {
            RawArea f;
            f.polygon = getPolygon(r);
            f.cls = static_cast<AreaClass>(r.u8());
            f.name = getString(r);
            if (r.failed() || r.remaining() != 0) break;
            out.areas.push_back(std::move(f));
            out.areas_counted.push_back(counted);
            return true;
        }
        case FeatureTag::PointLabel: {
            RawPointLabel f;
            f.kind = static_cast<LabelKind>(r.u8());
            f.subclass = r.u8();
            f.name = getString(r);
            f.pos.lat_deg = r.f64();
            f.pos.lon_deg = r.f64();
            f.importance = r.f32();
            f.id = r.i64();
            if (r.failed() || r.remaining() != 0) break;
            out.points.push_back(std::move(f));
            out.points_counted.push_back(counted);
            return true;
        }
        case FeatureTag::PlaceLabel: {
            RawAreaLabel f;
            f.polygon = getPolygon(r);
            f.subclass = r.u8();
            f.name = getString(r);
            f.importance = r.f32();
            if (r.failed() || r.remaining() != 0) break;
            out.places.push_back(std::move(f));
            out.places_counted.push_back(counted);
            return true;
        }
        case FeatureTag::GraphWay: {
            RawGraphWay f;
            f.id = r.i64();
            f.cls = static_cast<RoadClass>(r.u8());
            f.flags = r.u8();
            f.speed_kmh = r.f32();
            f.limit_forward_kmh = r.u16();
            f.limit_backward_kmh = r.u16();
            for (auto* lanes : {&f.lanes_forward, &f.lanes_backward}) {
                lanes->resize(count(r, 2));
                for (std::uint16_t& a : *lanes) a = r.u16();
            }
            f.oneway = r.u8() != 0;
            f.nodes.resize(count(r, 1));
            std::int64_t prev = 0;
            for (auto& n : f.nodes) {  // unsigned: damaged deltas wrap instead of overflowing
                prev = static_cast<std::int64_t>(static_cast<std::uint64_t>(prev) +
                                                 static_cast<std::uint64_t>(r.svarint()));
                n = prev;
            }
            f.points = getPoints(r);
            if (r.failed() || r.remaining() != 0) break;
            out.graph_ways.push_back(std::move(f));
            return true;
        }
        default: error = "unknown feature tag " + std::to_string(tag_byte & ~kRepeatFlag); return false;
    }
    error = r.failed() ? r.error() : std::to_string(r.remaining()) + " bytes left over after the feature";
    return false;
}

}  // namespace navmap::map::detail
