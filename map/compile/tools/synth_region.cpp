// SPDX-License-Identifier: Apache-2.0
#include "synth_region.h"

#include <osmium/builder/attr.hpp>
#include <osmium/handler.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/io/any_output.hpp>
#include <osmium/memory/buffer.hpp>
#include <osmium/visitor.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace navmap::map::tools {

namespace {

using Id = osmium::object_id_type;

/// Every id of one object type the source holds or refers to, sorted: its rank is the dense id
/// within one copy, so copy k's ids are k * size + rank + 1 and no two copies share one.
struct IdSpace {
    std::vector<Id> ids;
    void finish() {
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }
    [[nodiscard]] Id map(Id id, int copy) const {
        const auto rank = std::lower_bound(ids.begin(), ids.end(), id) - ids.begin();
        return static_cast<Id>(copy) * static_cast<Id>(ids.size()) + rank + 1;
    }
};

/// The source, kept whole (a country-sized region is made of many copies of a small extract).
class Collector : public osmium::handler::Handler {
public:
    explicit Collector(bool highways_only) : m_highways_only(highways_only) {}
    void node(const osmium::Node& n) {
        if (!n.location().valid()) return;
        buffer.add_item(n);
        buffer.commit();
        nodes.ids.push_back(n.id());
        south = std::min(south, n.location().lat());
        north = std::max(north, n.location().lat());
        west = std::min(west, n.location().lon());
        east = std::max(east, n.location().lon());
    }
    void way(const osmium::Way& w) {
        if (m_highways_only && !w.tags()["highway"]) return;
        buffer.add_item(w);
        buffer.commit();
        ways.ids.push_back(w.id());
        for (const auto& n : w.nodes()) {
            nodes.ids.push_back(n.ref());
            used_nodes.push_back(n.ref());
        }
    }
    void relation(const osmium::Relation& r) {
        if (m_highways_only) return;
        buffer.add_item(r);
        buffer.commit();
        relations.ids.push_back(r.id());
        for (const auto& m : r.members()) {
            if (m.type() == osmium::item_type::node) nodes.ids.push_back(m.ref());
            if (m.type() == osmium::item_type::way) ways.ids.push_back(m.ref());
            if (m.type() == osmium::item_type::relation) relations.ids.push_back(m.ref());
        }
    }
    osmium::memory::Buffer buffer{std::size_t{1} << 24, osmium::memory::Buffer::auto_grow::yes};
    IdSpace nodes, ways, relations;
    std::vector<Id> used_nodes;  // highways_only: the nodes the kept ways use
    double south = 90, north = -90, west = 180, east = -180;

private:
    bool m_highways_only;
};

std::vector<std::pair<std::string, std::string>> tagsOf(const osmium::TagList& tags) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& t : tags) out.emplace_back(t.key(), t.value());
    return out;
}

/// The source tile's heights (big-endian int16, void -32768), and its south-west corner.
struct Hgt {
    int size = 0;
    int lat0 = 0, lon0 = 0;
    std::vector<std::int16_t> h;
    [[nodiscard]] std::int16_t at(double lat, double lon) const {
        const double r = (lat0 + 1 - lat) * (size - 1), c = (lon - lon0) * (size - 1);
        if (r < -0.5 || c < -0.5 || r > size - 0.5 || c > size - 0.5) return -32768;
        const int ri = std::clamp(static_cast<int>(std::lround(r)), 0, size - 1);
        const int ci = std::clamp(static_cast<int>(std::lround(c)), 0, size - 1);
        return h[static_cast<std::size_t>(ri) * size + ci];
    }
};

Hgt readHgt(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path.string() + ": cannot read");
    std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
    Hgt hgt;
    hgt.size = static_cast<int>(std::lround(std::sqrt(static_cast<double>(bytes.size() / 2))));
    if (static_cast<std::size_t>(hgt.size) * hgt.size * 2 != bytes.size() || hgt.size < 2) {
        throw std::runtime_error(path.string() + ": not an SRTM tile (" + std::to_string(bytes.size()) + " bytes)");
    }
    const std::string name = path.filename().string();
    int lat = 0, lon = 0;
    char ns = 0, ew = 0;
    if (std::sscanf(name.c_str(), "%c%2d%c%3d", &ns, &lat, &ew, &lon) != 4 || (ns != 'N' && ns != 'S') ||
        (ew != 'E' && ew != 'W')) {
        throw std::runtime_error(path.string() + ": the name is not an SRTM tile's (N42E001.hgt)");
    }
    hgt.lat0 = ns == 'N' ? lat : -lat;
    hgt.lon0 = ew == 'E' ? lon : -lon;
    hgt.h.resize(bytes.size() / 2);
    for (std::size_t i = 0; i < hgt.h.size(); ++i) {
        hgt.h[i] = static_cast<std::int16_t>((static_cast<unsigned char>(bytes[2 * i]) << 8) |
                                             static_cast<unsigned char>(bytes[2 * i + 1]));
    }
    return hgt;
}

std::string hgtName(int lat, int lon) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%c%02d%c%03d.hgt", lat >= 0 ? 'N' : 'S', std::abs(lat), lon >= 0 ? 'E' : 'W',
                  std::abs(lon));
    return buf;
}

/// The region's DEM tiles beside its OSM file. Heights repeat with the copies: a point of copy
/// k's cell of the grid takes the source tile's height at the same place in the first copy's
/// cell; a point of no other copy's cell keeps the source's own height (void outside the source
/// tile). A tile that would be (almost) all void is not written.
void writeDems(const SynthRegionOptions& opt, const Collector& src, int rows, int cols, SynthRegion& region) {
    const Hgt hgt = readHgt(opt.dem);
    const double south = src.south + opt.shift_lat_deg, west = src.west + opt.shift_lon_deg;
    const bool shifted = opt.shift_lat_deg != 0.0 || opt.shift_lon_deg != 0.0;
    const double north = south + rows * region.step_lat, east = west + cols * region.step_lon;
    std::vector<char> bytes(static_cast<std::size_t>(hgt.size) * hgt.size * 2);
    for (int lat = static_cast<int>(std::floor(south)); lat < static_cast<int>(std::ceil(north)); ++lat) {
        for (int lon = static_cast<int>(std::floor(west)); lon < static_cast<int>(std::ceil(east)); ++lon) {
            std::size_t valid = 0;
            for (int r = 0; r < hgt.size; ++r) {
                const double la = lat + 1 - static_cast<double>(r) / (hgt.size - 1);
                const int row = static_cast<int>(std::floor((la - south) / region.step_lat));
                for (int c = 0; c < hgt.size; ++c) {
                    const double lo = lon + static_cast<double>(c) / (hgt.size - 1);
                    const int col = static_cast<int>(std::floor((lo - west) / region.step_lon));
                    const bool copy = row >= 0 && col >= 0 && row < rows && col < cols &&
                                      row * cols + col < opt.copies && (shifted || row * cols + col > 0);
                    const std::int16_t h = copy      ? hgt.at(la - opt.shift_lat_deg - row * region.step_lat,
                                                              lo - opt.shift_lon_deg - col * region.step_lon)
                                           : shifted ? std::int16_t{-32768}
                                                     : hgt.at(la, lo);
                    valid += h != -32768 ? 1 : 0;
                    const std::size_t i = (static_cast<std::size_t>(r) * hgt.size + c) * 2;
                    bytes[i] = static_cast<char>(static_cast<std::uint16_t>(h) >> 8);
                    bytes[i + 1] = static_cast<char>(static_cast<std::uint16_t>(h) & 0xff);
                }
            }
            // A tile the source only touches along its edge (shared border samples) is left out too.
            if (valid <= 2 * static_cast<std::size_t>(hgt.size)) continue;
            const std::filesystem::path path = opt.out_dir / hgtName(lat, lon);
            std::ofstream out(path, std::ios::binary | std::ios::trunc);
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            out.close();
            if (!out) throw std::runtime_error(path.string() + ": cannot write");
            region.dems.push_back(path);
        }
    }
    if (opt.log) opt.log("wrote " + std::to_string(region.dems.size()) + " DEM tiles");
}

/// The copies of the source into region.osm: nodes of every copy, then ways, then relations (the
/// order libosmium readers expect), with their counts and bounds in `region`.
void writeCopies(const SynthRegionOptions& opt, const Collector& src, int cols, SynthRegion& region) {
    auto offset = [&](int copy) {
        return std::pair<double, double>{opt.shift_lat_deg + (copy / cols) * region.step_lat,
                                         opt.shift_lon_deg + (copy % cols) * region.step_lon};
    };
    osmium::io::Header header;
    header.set("generator", "navmap-synth-region");
    osmium::io::Writer writer(region.osm.string(), header, osmium::io::overwrite::allow);
    using namespace osmium::builder::attr;  // NOLINT(google-build-using-namespace): the builder's attribute DSL
    std::vector<Id> node_refs;
    for (const auto kind : {osmium::item_type::node, osmium::item_type::way, osmium::item_type::relation}) {
        for (int copy = 0; copy < opt.copies; ++copy) {
            const auto [dlat, dlon] = offset(copy);
            osmium::memory::Buffer out(std::size_t{1} << 22, osmium::memory::Buffer::auto_grow::yes);
            for (const auto& item : src.buffer) {
                if (item.type() != kind) continue;
                if (kind == osmium::item_type::node) {
                    const auto& n = static_cast<const osmium::Node&>(item);
                    if (opt.highways_only && !std::binary_search(src.nodes.ids.begin(), src.nodes.ids.end(), n.id()))
                        continue;
                    const osmium::Location loc(n.location().lon() + dlon, n.location().lat() + dlat);
                    osmium::builder::add_node(out, _id(src.nodes.map(n.id(), copy)), _version(1), _location(loc),
                                              _tags(tagsOf(n.tags())));
                    ++region.nodes;
                    region.south = std::min(region.south, loc.lat());
                    region.north = std::max(region.north, loc.lat());
                    region.west = std::min(region.west, loc.lon());
                    region.east = std::max(region.east, loc.lon());
                } else if (kind == osmium::item_type::way) {
                    const auto& w = static_cast<const osmium::Way&>(item);
                    node_refs.clear();
                    for (const auto& n : w.nodes()) node_refs.push_back(src.nodes.map(n.ref(), copy));
                    osmium::builder::add_way(out, _id(src.ways.map(w.id(), copy)), _version(1), _nodes(node_refs),
                                             _tags(tagsOf(w.tags())));
                    ++region.ways;
                    region.way_nodes += node_refs.size();
                } else {
                    const auto& r = static_cast<const osmium::Relation&>(item);
                    std::vector<member_type> members;  // roles point into src.buffer
                    for (const auto& m : r.members()) {
                        const IdSpace& space = m.type() == osmium::item_type::node  ? src.nodes
                                               : m.type() == osmium::item_type::way ? src.ways
                                                                                    : src.relations;
                        members.emplace_back(m.type(), space.map(m.ref(), copy), m.role());
                    }
                    osmium::builder::add_relation(out, _id(src.relations.map(r.id(), copy)), _version(1),
                                                  _members(members), _tags(tagsOf(r.tags())));
                    ++region.relations;
                }
            }
            writer(std::move(out));
        }
    }
    writer.close();
}

}  // namespace

SynthRegion synthesizeRegion(const SynthRegionOptions& opt) {
    if (opt.copies < 1) throw std::runtime_error("copies must be at least 1");
    auto log = [&](const std::string& s) {
        if (opt.log) opt.log(s);
    };
    {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(opt.osm, ec))
            throw std::runtime_error(opt.osm.string() + ": no such file");
        if (!opt.dem.empty() && !std::filesystem::is_regular_file(opt.dem, ec))
            throw std::runtime_error(opt.dem.string() + ": no such file");
    }
    Collector src(opt.highways_only);
    try {
        osmium::io::Reader reader(opt.osm.string());
        osmium::apply(reader, src);
        reader.close();
    } catch (const std::exception& e) {
        throw std::runtime_error(opt.osm.string() + ": cannot read OSM data: " + e.what());
    }
    {
        std::error_code ec;
        std::filesystem::create_directories(opt.out_dir, ec);
        if (ec) throw std::runtime_error(opt.out_dir.string() + ": cannot create: " + ec.message());
    }
    if (opt.highways_only) {
        // Only the nodes the kept ways use.
        std::sort(src.used_nodes.begin(), src.used_nodes.end());
        src.nodes.ids = src.used_nodes;
    }
    src.nodes.finish();
    src.ways.finish();
    src.relations.finish();

    SynthRegion region;
    region.south = 90;
    region.north = -90;
    region.west = 180;
    region.east = -180;
    const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(opt.copies))));
    const int rows = (opt.copies + cols - 1) / cols;
    region.step_lon = (src.east - src.west) + opt.gap_deg;
    region.step_lat = (src.north - src.south) + opt.gap_deg;
    region.osm = opt.out_dir / "region.osm.pbf";
    log("source: " + std::to_string(src.nodes.ids.size()) + " node ids, " + std::to_string(src.ways.ids.size()) +
        " way ids, " + std::to_string(src.relations.ids.size()) + " relation ids; " + std::to_string(opt.copies) +
        " copies, " + std::to_string(cols) + " per row, steps " + std::to_string(region.step_lat) + " deg x " +
        std::to_string(region.step_lon) + " deg");

    writeCopies(opt, src, cols, region);
    log("wrote " + region.osm.string() + ": " + std::to_string(region.nodes) + " nodes, " +
        std::to_string(region.ways) + " ways, " + std::to_string(region.relations) + " relations");

    if (!opt.dem.empty()) writeDems(opt, src, rows, cols, region);
    return region;
}

}  // namespace navmap::map::tools
