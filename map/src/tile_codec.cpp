// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/tile_codec.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "byte_io.h"
#include "navmap/common/check.h"
#include "navmap/map/store_info.h"

namespace navmap::map {

using detail::ByteReader;
using detail::ByteWriter;

namespace {

constexpr std::uint16_t kMaxDemSize = 4097;

/// Adds deltas from untrusted input without signed-overflow UB.
std::int64_t wrappingAdd(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b));
}

std::int64_t quantize(float v) { return std::llround(static_cast<double>(v) / kCoordQuantum); }

void writePoints(ByteWriter& w, const std::vector<LocalPoint>& pts) {
    w.varint(pts.size());
    std::int64_t px = 0, py = 0;
    for (const auto& p : pts) {
        const std::int64_t qx = quantize(p.x), qy = quantize(p.y);
        w.svarint(qx - px);
        w.svarint(qy - py);
        px = qx;
        py = qy;
    }
}

void readPoints(ByteReader& r, std::vector<LocalPoint>& pts) {
    const std::size_t n = r.count(2, "point");
    pts.resize(n);
    std::int64_t x = 0, y = 0;
    for (auto& p : pts) {
        x = wrappingAdd(x, r.svarint());
        y = wrappingAdd(y, r.svarint());
        p = {static_cast<float>(x * kCoordQuantum), static_cast<float>(y * kCoordQuantum)};
    }
}

void writePoint(ByteWriter& w, LocalPoint p) {
    w.svarint(quantize(p.x));
    w.svarint(quantize(p.y));
}

LocalPoint readPoint(ByteReader& r) {
    const auto x = r.svarint();
    const auto y = r.svarint();
    return {static_cast<float>(x * kCoordQuantum), static_cast<float>(y * kCoordQuantum)};
}

void writePolygon(ByteWriter& w, const Polygon& poly) {
    NAVMAP_CHECK(poly.indices.empty() || std::ranges::max(poly.indices) < poly.vertices.size(),
                 "polygon index past its vertices");
    writePoints(w, poly.vertices);
    w.varint(poly.ring_ends.size());
    std::uint32_t prev = 0;
    for (auto e : poly.ring_ends) {
        w.varint(e - prev);
        prev = e;
    }
    w.varint(poly.indices.size());
    for (auto i : poly.indices) w.varint(i);
}

void readPolygon(ByteReader& r, Polygon& poly) {
    readPoints(r, poly.vertices);
    const std::size_t rings = r.count(1, "ring");
    poly.ring_ends.resize(rings);
    std::uint64_t end = 0;
    for (auto& e : poly.ring_ends) {
        end += r.varint();
        if (end > poly.vertices.size()) {
            r.fail("ring end beyond vertex count");
            return;
        }
        e = static_cast<std::uint32_t>(end);
    }
    const std::size_t n = r.count(1, "index");
    if (n % 3 != 0) {
        r.fail("index count not a multiple of 3");
        return;
    }
    poly.indices.resize(n);
    for (auto& i : poly.indices) {
        const std::uint64_t v = r.varint();
        if (v >= poly.vertices.size()) {
            r.fail("triangle index out of range");
            return;
        }
        i = static_cast<std::uint32_t>(v);
    }
}

constexpr std::uint16_t kMaxCoverSize = 2048;
constexpr std::uint16_t kMaxGridSize = 1025;

// Ortho layer kinds as stored (docs/tile-store.md "Ortho layers").
enum LayerKind : std::uint8_t {
    kCover = 0,
    kClimate,
    kTempDec,
    kTempJul,
    kPrecipDec,
    kPrecipJul,
    kLights,
    kElevation,
    kSlope,
    kAspect,
    kLayerKinds
};
constexpr const char* kLayerNames[kLayerKinds] = {"cover",      "climate", "temp_dec",  "temp_jul", "precip_dec",
                                                  "precip_jul", "lights",  "elevation", "slope",    "aspect"};

// The 8-bit layer of a kind (null for elevation); for const and mutable layers alike.
template <typename Layers>
auto byteLayer(Layers& o, int kind) -> decltype(&o.cover) {
    switch (kind) {
        case kCover: return &o.cover;
        case kClimate: return &o.climate;
        case kTempDec: return &o.temp_dec;
        case kTempJul: return &o.temp_jul;
        case kPrecipDec: return &o.precip_dec;
        case kPrecipJul: return &o.precip_jul;
        case kLights: return &o.lights;
        case kSlope: return &o.slope;
        case kAspect: return &o.aspect;
        default: return nullptr;
    }
}

void writeOrtho(ByteWriter& w, const ortho::OrthoLayers& o) {
    if (o.empty()) {
        w.u8(0);
        return;
    }
    w.u8(kLayerKinds);
    for (int kind = 0; kind < kLayerKinds; ++kind) {
        const std::uint16_t side = kind == kCover ? o.cover_size : o.grid_size;
        w.u8(static_cast<std::uint8_t>(kind));
        w.u16(side);
        w.u16(side);
        if (kind == kElevation) {
            std::int64_t prev = 0;
            for (std::int16_t v : o.elevation) {
                w.svarint(v - prev);
                prev = v;
            }
        } else {
            const auto& bytes = *byteLayer(o, kind);
            w.raw(bytes.data(), bytes.size());
        }
    }
}

void readOrtho(ByteReader& r, ortho::OrthoLayers& o) {
    const std::uint8_t count = r.u8();
    if (r.failed() || count == 0) return;
    if (count != kLayerKinds) {
        r.fail("ortho layer count " + std::to_string(count) + ", expected " + std::to_string(kLayerKinds));
        return;
    }
    for (int kind = 0; kind < kLayerKinds && !r.failed(); ++kind) {
        const std::uint8_t stored = r.u8();
        const std::uint16_t width = r.u16(), height = r.u16();
        if (r.failed()) return;
        if (stored != kind) {
            r.fail("ortho layer " + std::to_string(stored) + " where " + kLayerNames[kind] + " belongs");
            return;
        }
        if (kind == kCover) {
            if (width != height || width == 0 || width > kMaxCoverSize) {
                r.fail("ortho layer cover is " + std::to_string(width) + "x" + std::to_string(height) +
                       ", expected a square of 1.." + std::to_string(kMaxCoverSize));
                return;
            }
            o.cover_size = width;
        } else if (kind == kClimate) {
            if (width != height || width < 2 || width > kMaxGridSize) {
                r.fail("ortho layer climate is " + std::to_string(width) + "x" + std::to_string(height) +
                       ", expected a square of 2.." + std::to_string(kMaxGridSize));
                return;
            }
            o.grid_size = width;
        } else if (width != o.grid_size || height != o.grid_size) {
            r.fail(std::string("ortho layer ") + kLayerNames[kind] + " is " + std::to_string(width) + "x" +
                   std::to_string(height) + ", expected " + std::to_string(o.grid_size) + "x" +
                   std::to_string(o.grid_size) + " (the grid size)");
            return;
        }
        const std::size_t n = std::size_t{width} * height;
        if (kind == kElevation) {
            if (n > r.remaining()) {
                r.fail("truncated ortho layer elevation");
                return;
            }
            o.elevation.resize(n);
            std::int64_t v = 0;
            for (auto& e : o.elevation) {
                v = wrappingAdd(v, r.svarint());
                if (v < -32768 || v > 32767) {
                    r.fail("ortho elevation out of range");
                    return;
                }
                e = static_cast<std::int16_t>(v);
            }
            continue;
        }
        const auto bytes = r.bytes(n);
        if (r.failed()) return;
        std::vector<std::uint8_t>& dst = *byteLayer(o, kind);
        dst.assign(bytes.begin(), bytes.end());
        const int limit = kind == kCover ? ortho::kCoverCodeCount : kind == kClimate ? ortho::kClimateCodeCount : 256;
        for (std::uint8_t b : dst) {
            if (b >= limit) {
                r.fail(std::string("bad ") + kLayerNames[kind] + " class " + std::to_string(b));
                return;
            }
        }
    }
}

}  // namespace

std::vector<std::uint8_t> encodeTile(const Tile& t) {
    ByteWriter w;
    w.u32(kTilePayloadMagic);
    w.u8(t.id.level);
    w.u32(t.id.x);
    w.u32(t.id.y);
    w.f64(t.origin_x);
    w.f64(t.origin_y);
    w.f64(t.size_m);

    w.varint(t.roads.size());
    for (const auto& road : t.roads) {
        w.u8(static_cast<std::uint8_t>(road.cls));
        w.u8(road.flags);
        w.u8(static_cast<std::uint8_t>(road.layer));
        w.u16(road.maxspeed_kmh);
        w.str(road.name);
        w.str(road.ref);
        w.svarint(road.osm_id);
        writePoints(w, road.points);
    }
    w.varint(t.buildings.size());
    for (const auto& b : t.buildings) {
        w.f32(b.height_m);
        w.f32(b.min_height_m);
        w.svarint(b.osm_id);
        writePolygon(w, b.footprint);
    }
    w.varint(t.areas.size());
    for (const auto& a : t.areas) {
        w.u8(static_cast<std::uint8_t>(a.cls));
        w.str(a.name);
        w.svarint(a.osm_id);
        writePolygon(w, a.polygon);
    }
    w.varint(t.labels.size());
    for (const auto& l : t.labels) {
        w.u8(static_cast<std::uint8_t>(l.kind));
        w.u8(l.subclass);
        w.str(l.name);
        writePoint(w, l.anchor);
        writePoint(w, l.segment_start);
        writePoint(w, l.segment_end);
        w.f32(l.importance);
        w.svarint(l.osm_id);
    }
    w.u16(t.dem.size);
    if (t.dem.size > 0) {
        w.f32(t.dem.spacing_m);
        w.f32(t.dem.coverage);
        std::int64_t prev = 0;
        for (float h : t.dem.heights) {
            const std::int64_t q = std::llround(h / kHeightQuantum);
            w.svarint(q - prev);
            prev = q;
        }
    }
    writeOrtho(w, t.ortho);
    return std::move(w.bytes());
}

bool decodeTile(std::span<const std::uint8_t> bytes, Tile& t, std::string& error) {
    ByteReader r(bytes);
    t = Tile{};
    if (r.u32() != kTilePayloadMagic) {
        error = "not a tile payload (bad magic)";
        return false;
    }
    t.id.level = r.u8();
    t.id.x = r.u32();
    t.id.y = r.u32();
    t.origin_x = r.f64();
    t.origin_y = r.f64();
    t.size_m = r.f64();
    if (!r.failed() && (t.id.level > 27 || !std::isfinite(t.origin_x) || !std::isfinite(t.origin_y) ||
                        !(t.size_m > 0) || !std::isfinite(t.size_m))) {
        r.fail("bad tile header");
    }

    t.roads.resize(r.count(8, "road"));
    for (auto& road : t.roads) {
        const std::uint8_t cls = r.u8();
        if (cls >= kRoadClassCount) r.fail("bad road class " + std::to_string(cls));
        road.cls = static_cast<RoadClass>(cls);
        road.flags = r.u8();
        road.layer = static_cast<std::int8_t>(r.u8());
        road.maxspeed_kmh = r.u16();
        road.name = r.str();
        road.ref = r.str();
        road.osm_id = r.svarint();
        readPoints(r, road.points);
        if (r.failed()) break;
    }
    t.buildings.resize(r.count(12, "building"));
    for (auto& b : t.buildings) {
        b.height_m = r.f32();
        b.min_height_m = r.f32();
        b.osm_id = r.svarint();
        readPolygon(r, b.footprint);
        if (r.failed()) break;
    }
    t.areas.resize(r.count(5, "area"));
    for (auto& a : t.areas) {
        const std::uint8_t cls = r.u8();
        if (cls >= kAreaClassCount) r.fail("bad area class " + std::to_string(cls));
        a.cls = static_cast<AreaClass>(cls);
        a.name = r.str();
        a.osm_id = r.svarint();
        readPolygon(r, a.polygon);
        if (r.failed()) break;
    }
    t.labels.resize(r.count(14, "label"));
    for (auto& l : t.labels) {
        const std::uint8_t kind = r.u8();
        if (kind > static_cast<std::uint8_t>(LabelKind::Area)) r.fail("bad label kind " + std::to_string(kind));
        l.kind = static_cast<LabelKind>(kind);
        l.subclass = r.u8();
        l.name = r.str();
        l.anchor = readPoint(r);
        l.segment_start = readPoint(r);
        l.segment_end = readPoint(r);
        l.importance = r.f32();
        l.osm_id = r.svarint();
        if (r.failed()) break;
    }
    t.dem.size = r.u16();
    if (!r.failed() && t.dem.size > 0) {
        if (t.dem.size > kMaxDemSize || std::size_t{t.dem.size} * t.dem.size > r.remaining()) {
            r.fail("implausible DEM size " + std::to_string(t.dem.size));
        } else {
            t.dem.spacing_m = r.f32();
            t.dem.coverage = r.f32();
            t.dem.heights.resize(std::size_t{t.dem.size} * t.dem.size);
            std::int64_t q = 0;
            for (auto& h : t.dem.heights) {
                q = wrappingAdd(q, r.svarint());
                h = static_cast<float>(q * kHeightQuantum);
            }
        }
    }
    if (!r.failed()) readOrtho(r, t.ortho);
    if (!r.failed() && r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " trailing bytes");
    if (r.failed()) {
        error = r.error();
        t = Tile{};
        return false;
    }
    return true;
}

}  // namespace navmap::map
