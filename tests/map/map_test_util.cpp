// SPDX-License-Identifier: Apache-2.0
#include "map_test_util.h"

#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

namespace navmap::map::test {

ScratchDir::ScratchDir(const std::string& name)
    : m_path(std::filesystem::temp_directory_path() / ("navmap-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(m_path);
    std::filesystem::create_directories(m_path);
}

ScratchDir::~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
}

Tile sampleTile(TileId id, double origin_x, double origin_y, double size_m) {
    Tile t;
    t.id = id;
    t.origin_x = origin_x;
    t.origin_y = origin_y;
    t.size_m = size_m;
    Road r;
    r.points = {{0.0f, 0.0f}, {12.34f, 56.78f}, {1999.99f, 1000.5f}};
    r.name = "Carrer de la Unió";
    r.ref = "CG-3";
    r.osm_id = 123456789;
    r.cls = RoadClass::Primary;
    r.flags = road_flags::kOneway | road_flags::kBridge;
    r.layer = -2;
    r.maxspeed_kmh = 50;
    t.roads.push_back(r);
    Building b;
    b.footprint.vertices = {{10, 10}, {20, 10}, {20, 20}, {10, 20}};
    b.footprint.ring_ends = {4};
    b.footprint.indices = {0, 1, 2, 0, 2, 3};
    b.height_m = 12.5f;
    b.min_height_m = 3.0f;
    b.osm_id = -42;
    t.buildings.push_back(b);
    Area a;
    a.polygon.vertices = {{0, 0}, {100, 0}, {100, 100}};
    a.polygon.ring_ends = {3};
    a.polygon.indices = {0, 1, 2};
    a.cls = AreaClass::Forest;
    a.name = "Bosc de l'Estany";
    t.areas.push_back(a);
    Label l;
    l.kind = LabelKind::Place;
    l.subclass = static_cast<std::uint8_t>(PlaceClass::Town);
    l.name = "Sant Julià de Lòria";
    l.anchor = l.segment_start = l.segment_end = {500.25f, 600.75f};
    l.importance = 0.8f;
    l.osm_id = 7;
    t.labels.push_back(l);
    t.dem.size = 5;
    t.dem.spacing_m = static_cast<float>(size_m / 4);
    t.dem.coverage = 1.0f;
    for (int i = 0; i < 25; ++i)
        t.dem.heights.push_back(1000.0f + 10.5f * static_cast<float>(i % 7) - 3.2f * static_cast<float>(i));
    return t;
}

std::filesystem::path repoData(const std::string& file) {
    return std::filesystem::path(NAVMAP_SOURCE_DIR) / "data" / file;
}

bool withFileSizeLimit(std::uint64_t bytes, const std::function<void()>& f) {
    struct sigaction ignore {
    }, old{};
    ignore.sa_handler = SIG_IGN;
    if (::sigaction(SIGXFSZ, &ignore, &old) != 0) return false;
    rlimit saved{};
    if (::getrlimit(RLIMIT_FSIZE, &saved) != 0) {
        ::sigaction(SIGXFSZ, &old, nullptr);
        return false;
    }
    rlimit small = saved;
    small.rlim_cur = bytes;
    if (::setrlimit(RLIMIT_FSIZE, &small) != 0) {
        ::sigaction(SIGXFSZ, &old, nullptr);
        return false;
    }
    f();
    ::setrlimit(RLIMIT_FSIZE, &saved);
    ::sigaction(SIGXFSZ, &old, nullptr);
    return true;
}

}  // namespace navmap::map::test
