// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/pn2.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace navmap::map::ortho {

namespace {

constexpr double kUnitDeg = 1.0 / 120.0;  // half an arc minute

enum Kind : std::uint8_t {
    kLineString = 0,
    kLinearRing = 1,
    kOuterBoundary = 2,
    kInnerBoundary = 3,
    kMultiGeometry = 4
};

class Reader {
public:
    Reader(const std::vector<std::uint8_t>& bytes, const std::string& name) : m_bytes(bytes), m_name(name) {}

    std::uint8_t u8(const char* what) {
        need(1, what);
        return m_bytes[m_pos++];
    }
    std::uint32_t u32(const char* what) {
        need(4, what);
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v = (v << 8) | m_bytes[m_pos++];
        return v;
    }
    std::int16_t i16(const char* what) {
        need(2, what);
        const auto v = static_cast<std::uint16_t>((m_bytes[m_pos] << 8) | m_bytes[m_pos + 1]);
        m_pos += 2;
        return static_cast<std::int16_t>(v);
    }
    std::int8_t i8(const char* what) { return static_cast<std::int8_t>(u8(what)); }
    [[nodiscard]] std::size_t position() const { return m_pos; }
    [[nodiscard]] std::size_t remaining() const { return m_bytes.size() - m_pos; }
    [[noreturn]] void fail(const std::string& problem) const {
        throw Pn2Error(m_name + ": " + problem + " at byte " + std::to_string(m_pos));
    }

private:
    void need(std::size_t n, const char* what) const {
        if (m_bytes.size() - m_pos < n) {
            throw Pn2Error(m_name + ": truncated at byte " + std::to_string(m_pos) + " (" + what + ")");
        }
    }
    const std::vector<std::uint8_t>& m_bytes;
    const std::string& m_name;
    std::size_t m_pos = 0;
};

GeoCoordinate point(Reader& r, int lat, int lon) {
    if (lat < -90 * 120 || lat > 90 * 120 || lon < -180 * 120 || lon > 180 * 120) {
        r.fail("coordinate out of range (lat " + std::to_string(lat * kUnitDeg) + ", lon " +
               std::to_string(lon * kUnitDeg) + ")");
    }
    return {lat * kUnitDeg, lon * kUnitDeg};
}

std::vector<GeoCoordinate> readNodes(Reader& r, std::uint32_t nodes) {
    // Each node takes at least 6 bytes: a count beyond what is left is a damaged file, not a
    // reason to reserve gigabytes.
    if (nodes > r.remaining() / 6) r.fail("node count " + std::to_string(nodes) + " exceeds the file");
    std::vector<GeoCoordinate> pts;
    pts.reserve(nodes);
    for (std::uint32_t n = 0; n < nodes; ++n) {
        const int lat = r.i16("node latitude"), lon = r.i16("node longitude");
        const int children = r.i16("child count");
        if (children < 0) r.fail("negative child count");
        pts.push_back(point(r, lat, lon));
        for (int c = 0; c < children; ++c) {
            const int dlat = r.i8("child latitude"), dlon = r.i8("child longitude");
            pts.push_back(point(r, lat + dlat, lon + dlon));
        }
    }
    return pts;
}

}  // namespace

Pn2File parsePn2(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    Reader r(bytes, name);
    const std::uint8_t version = r.u8("header");
    if (version != 2) r.fail("unsupported .pn2 version " + std::to_string(version) + " (this reader reads version 2)");
    const std::uint32_t records = r.u32("header");
    const bool colours = r.u8("header") != 0;
    Pn2File out;
    Pn2Polygon* open = nullptr;  // the polygon that inner boundaries attach to
    std::uint32_t read = 0;
    int parts_left = 0;  // records still belonging to the last multi-geometry
    while (read < records) {
        const std::uint8_t kind = r.u8("record kind");
        const std::uint32_t id = r.u32("record id");
        if (kind > kMultiGeometry) r.fail("unknown record kind " + std::to_string(kind));
        // The colour index belongs to a whole feature: a multi-geometry has it, its parts and
        // inner boundaries do not.
        if (colours && kind != kInnerBoundary && parts_left == 0) (void)r.u8("colour index");
        if (kind == kMultiGeometry) {
            parts_left = r.u8("part count");  // the parts follow as records of their own
            continue;
        }
        if (parts_left > 0) --parts_left;
        std::vector<GeoCoordinate> pts = readNodes(r, r.u32("node count"));
        ++read;
        switch (kind) {
            case kLineString:
                out.lines.push_back(std::move(pts));
                open = nullptr;
                break;
            case kLinearRing:
            case kOuterBoundary:
                out.polygons.push_back({id, std::move(pts), {}});
                open = &out.polygons.back();
                break;
            case kInnerBoundary:
                if (!open) r.fail("inner boundary without an outer boundary before it");
                open->holes.push_back(std::move(pts));
                break;
            default: break;
        }
    }
    if (r.remaining() != 0)
        r.fail(std::to_string(r.remaining()) + " bytes after the last of " + std::to_string(records) + " records");
    out.records = read;
    return out;
}

Pn2File readPn2(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Pn2Error("open(" + path.string() + "): " + std::strerror(errno));
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw Pn2Error("read(" + path.string() + "): " + std::strerror(errno));
    return parsePn2(bytes, path.filename().string());
}

}  // namespace navmap::map::ortho
