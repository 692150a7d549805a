// SPDX-License-Identifier: Apache-2.0
// The read stage of compileStore (compile_stages.h): the DEM files and the OSM file, whose
// libosmium handlers classify the tags as it streams.
#include "compile_stages.h"

// GCC 12 reports a false -Wstringop-overread inside libosmium's area builder once it is
// inlined here (osmium/builder/osm_object_builder.hpp); the code reads a NUL-terminated tag.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include <osmium/area/assembler.hpp>
#include <osmium/area/multipolygon_manager.hpp>
#include <osmium/handler/node_locations_for_ways.hpp>
#include <osmium/index/map/flex_mem.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/relations/relations_manager.hpp>
#include <osmium/tags/tags_filter.hpp>
#include <osmium/visitor.hpp>

#include <algorithm>
#include <cstdio>

#include "file_node_index.h"
#include "multipolygon_spill.h"
#include "navmap/map/compile/tag_rules.h"
#include "navmap/map/dem.h"
#include "osm_limits.h"

namespace navmap::map::detail {

namespace {

std::string fmtSeconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%6.2fs", s);
    return buf;
}

/// osmium::relations::read_relations() with OsmLimits in front of the manager: a relation beyond
/// the member cap stops the compile, and the manager sees each member of a relation once.
template <typename Manager>
void readRelations(const osmium::io::File& file, Manager& manager, OsmLimits& limits) {
    osmium::io::Reader reader{file, osmium::osm_entity_bits::relation};
    while (osmium::memory::Buffer buffer = reader.read()) {
        for (const auto& relation : buffer.select<osmium::Relation>()) manager.relation(limits.uniqueMembers(relation));
    }
    reader.close();
    manager.prepare_for_lookup();
}

/// The handlers of the second pass and where their features go: after each buffer into the
/// bounds, then into memory or the spill file, in input order per kind.
class OsmCollector {
public:
    OsmCollector(const OsmReadOptions& options, OsmInput& out)
        : buildings(options.default_building_height_m), m_options(options), m_out(out) {}

    RoadHandler roads;
    GraphHandler graph_ways;
    BuildingHandler buildings;
    AreaHandler areas;
    LabelHandler labels;
    CoastlineHandler coast;

    void drain() {
        RawFeatures& all = m_out.features;
        LatLonBounds& b = m_out.bounds;
        take(roads.roads, all.roads, m_out.roads, [&](const RawRoad& r) {
            for (const auto& p : r.points) b.grow(p);
        });
        take(buildings.buildings, all.buildings, m_out.buildings, [&](const RawBuilding& f) {
            for (const auto& r : f.polygon.outers)
                for (const auto& p : r) b.grow(p);
        });
        take(areas.areas, all.areas, m_out.areas, [&](const RawArea& a) {
            for (const auto& r : a.polygon.outers)
                for (const auto& p : r) b.grow(p);
        });
        take(labels.points, all.points, m_out.points, [&](const RawPointLabel& l) { b.grow(l.pos); });
        take(labels.places, all.places, m_out.places, [](const RawAreaLabel&) {});
        if (!m_options.with_graph) {
            graph_ways.ways.clear();
        } else if (m_options.spill) {
            for (const auto& w : graph_ways.ways) m_options.spill->graph->append(encodeFeature(w));
            graph_ways.ways.clear();
        } else {
            for (auto& w : graph_ways.ways) all.graph_ways.push_back(std::move(w));
            graph_ways.ways.clear();
        }
    }

private:
    template <typename From, typename To, typename Bounds>
    void take(From& from, To& to, std::size_t& n, Bounds&& bounds) {
        for (auto& f : from) {
            bounds(f);
            if (m_options.spill) {
                m_options.spill->features->append(encodeFeature(f));
            } else {
                to.push_back(std::move(f));
            }
        }
        n += from.size();
        from.clear();
    }

    const OsmReadOptions& m_options;
    OsmInput& m_out;
};

/// The second pass over `file`, with the multipolygon manager's handler last.
template <typename Locations, typename MpHandler>
void readFeatures(const osmium::io::File& file, OsmLimits& limits, Locations& locations, OsmCollector& c,
                  MpHandler&& mp_handler, const OsmInput& in, CompileLog& log) {
    osmium::io::Reader reader{file, osmium::io::read_meta::no};
    const std::size_t total = std::max<std::size_t>(reader.file_size(), 1);
    double last_log = log.elapsed();
    while (osmium::memory::Buffer buffer = reader.read()) {
        osmium::apply(buffer, limits, locations, c.roads, c.graph_ways, c.labels, c.coast, mp_handler);
        c.drain();
        if (log.elapsed() - last_log >= 1.0) {  // progress once a second on long runs
            last_log = log.elapsed();
            const double pct = 100.0 * static_cast<double>(reader.offset()) / static_cast<double>(total);
            log.log("reading " + std::to_string(static_cast<int>(std::min(pct, 100.0))) + "% of the file read ahead; " +
                    std::to_string(in.roads) + " roads, " + std::to_string(in.buildings) + " buildings so far");
        }
    }
    c.drain();
    log.log("read " + std::to_string(in.roads) + " roads, " + std::to_string(in.buildings) + " buildings, " +
            std::to_string(in.areas) + " areas, " + std::to_string(in.points) + " point labels");
    if (c.graph_ways.turn_lane_ways > 0 || c.graph_ways.turn_lane_values_ignored > 0 ||
        c.graph_ways.turn_lane_tags_dropped > 0) {
        log.log("turn lanes on " + std::to_string(c.graph_ways.turn_lane_ways) + " ways; " +
                std::to_string(c.graph_ways.turn_lane_values_ignored) + " unknown values ignored, " +
                std::to_string(c.graph_ways.turn_lane_tags_dropped) + " tags not used");
    }
    reader.close();
}

/// Both passes: relations, then everything with the multipolygon manager assembling areas.
void readPasses(const std::string& osm_name, const OsmReadOptions& options, OsmCollector& c, OsmInput& in,
                CompileLog& log) {
    const osmium::io::File file(osm_name);
    osmium::TagsFilter filter{false};
    for (const char* key : kAreaTagKeys) filter.add_rule(true, osmium::TagMatcher{key});
    osmium::area::Assembler::config_type cfg;
    cfg.keep_type_tag = true;  // areaClassFromTags: a type=boundary relation is never an area
    std::unique_ptr<NodeIndex> index;
    if (options.spill) {
        index = std::make_unique<FileNodeIndex>(options.spill->dir / "nodes.index");
    } else {
        index = std::make_unique<osmium::index::map::FlexMem<osmium::unsigned_object_id_type, osmium::Location>>();
    }
    osmium::handler::NodeLocationsForWays<NodeIndex> locations{*index};
    OsmLimits limits{osm_name};  // first in each pass: nothing copies an object beyond the caps
    locations.ignore_errors();   // ways crossing the extract border keep their inside parts
    auto areas_out = [&](osmium::memory::Buffer&& buffer) { osmium::apply(buffer, c.buildings, c.areas, c.labels); };
    log.log("reading relations of " + std::filesystem::path(osm_name).filename().string());
    if (options.spill) {
        // Member ways of multipolygon relations wait in a spill file, not in memory, until
        // their relation is complete (multipolygon_spill.h); the same areas in the same order.
        DiskMultipolygonManager mp{cfg, filter, options.spill->dir / "multipolygon-ways.spill"};
        readRelations(file, mp, limits);
        readFeatures(file, limits, locations, c, mp.handler(areas_out), in, log);
        log.log("multipolygons: " + std::to_string(mp.completeRelations()) + " relations complete, " +
                std::to_string(mp.memberWays()) + " member ways spilled");
    } else {
        osmium::area::MultipolygonManager<osmium::area::Assembler> mp{cfg, filter};
        readRelations(file, mp, limits);
        readFeatures(file, limits, locations, c, mp.handler(areas_out), in, log);
    }
    in.repeated_members = limits.repeatedMembers();
    in.turn_lane_ways = c.graph_ways.turn_lane_ways;
    in.turn_lane_values_ignored = c.graph_ways.turn_lane_values_ignored;
    in.turn_lane_tags_dropped = c.graph_ways.turn_lane_tags_dropped;
    if (limits.relationsWithRepeats() > 0) {
        log.warn(std::to_string(limits.relationsWithRepeats()) +
                 " relation(s) listed members more than once (relation " +
                 std::to_string(limits.firstRelationWithRepeats()) +
                 " first): " + std::to_string(limits.repeatedMembers()) + " repeats left out");
    }
}

}  // namespace

CompileLog::CompileLog(std::function<void(const std::string&)> sink, std::vector<std::string>& warnings)
    : m_sink(std::move(sink)), m_warnings(warnings), m_start(std::chrono::steady_clock::now()) {}

double CompileLog::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void CompileLog::log(const std::string& msg) const {
    if (m_sink) m_sink("[" + fmtSeconds(elapsed()) + "] " + msg);
}

void CompileLog::warn(const std::string& msg) {
    m_warnings.push_back(msg);
    log("warning: " + msg);
}

std::string mib(std::uint64_t bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / 1048576.0);
    return buf;
}

void noteAllVoidDem(DemInput& dem, const std::filesystem::path& path, std::size_t samples, CompileLog& log) {
    dem.all_void.push_back(path);
    log.warn("DEM " + path.filename().string() + ": all " + std::to_string(samples) +
             " samples are voids: it gives no heights, its area is flat (0 m)");
}

DemInput readDems(const std::vector<std::filesystem::path>& files, std::uint64_t memory_limit_mib, CompileLog& log) {
    // In memory every grid is loaded now; bounded, each is read when first sampled and dropped
    // again while a third of the limit is full (a band samples only the DEM under its columns).
    DemInput out;
    for (const auto& path : files) {
        if (memory_limit_mib > 0) {
            const HgtShape shape = probeHgt(path);  // DemError names the file
            log.log("DEM " + path.filename().string() + ": " + std::to_string(shape.side) + "x" +
                    std::to_string(shape.side) + ", read when first needed");
            out.spacing_m = shape.spacing * 111320.0;
            out.dems.addFile(path);
            continue;
        }
        Dem dem = loadHgt(path);  // DemError names the file
        log.log("DEM " + path.filename().string() + ": " + std::to_string(dem.rows) + "x" + std::to_string(dem.cols) +
                ", " + std::to_string(dem.void_count) + " void samples");
        if (dem.void_count == dem.heights.size()) noteAllVoidDem(out, path, dem.void_count, log);
        out.voids_filled += fillVoids(dem);
        out.spacing_m = dem.spacing * 111320.0;
        out.dems.add(std::move(dem));
    }
    if (memory_limit_mib > 0) out.dems.setBudget((memory_limit_mib << 20) / 3);
    if (out.dems.empty()) log.warn("no DEM given: terrain is flat (0 m)");
    return out;
}

Spill::Spill(const std::filesystem::path& parent, const std::function<void(const std::string&)>& log)
    : dir(parent, log) {
    features.emplace(dir / "features.spill", std::size_t{1} << 20);
    graph.emplace(dir / "graph.spill", std::size_t{1} << 20);
}

void LatLonBounds::grow(const GeoCoordinate& p) {
    south = std::min(south, p.lat_deg);
    north = std::max(north, p.lat_deg);
    west = std::min(west, p.lon_deg);
    east = std::max(east, p.lon_deg);
}

void checkOsmFile(const std::filesystem::path& osm) {
    // A regular file, opened without blocking: /dev/zero or a FIFO is named as what it is.
    const UntrustedFile file = UntrustedFile::open(osm, kOsmInput);
    if (!file.ok()) throw CompileError(file.error());
}

OsmInput readOsm(const std::filesystem::path& osm, const OsmReadOptions& options, CompileLog& log) {
    const std::string osm_name = osm.string();
    OsmInput in;
    OsmCollector collector(options, in);
    try {
        readPasses(osm_name, options, collector, in, log);
    } catch (const CompileError&) {
        throw;
    } catch (const std::exception& e) {
        throw CompileError(osm_name + ": cannot read OSM data: " + e.what());
    }
    if (options.spill) {
        options.spill->features->close();
        options.spill->graph->close();
        std::error_code ec;
        std::filesystem::remove(options.spill->dir / "nodes.index", ec);  // no longer needed: free the disk
        std::filesystem::remove(options.spill->dir / "multipolygon-ways.spill", ec);
    }
    if (in.roads == 0 && in.buildings == 0 && in.areas == 0 && in.points == 0 && collector.coast.ways.empty()) {
        throw CompileError(osm_name + ": no map features (roads, buildings, areas, places, coastlines) found");
    }
    in.coast = std::move(collector.coast.ways);
    return in;
}

}  // namespace navmap::map::detail
