// SPDX-License-Identifier: Apache-2.0
// Pixels of map data that Andorra lacks: the sea (assembled from coastline ways by
// navmap-compile), a road tunnel under a hill, and the ground beyond the store's data. The coast
// and the hill are synthetic OSM and SRTM files compiled in the test. Mesa llvmpipe through EGL.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "navmap/map/compile/compiler.h"
#include "navmap/map/tile_store.h"
#include "navmap/render/renderer.h"
#include "synthetic_tile.h"
#include "tile_mesh.h"

namespace {

using namespace navmap::render;
namespace map = navmap::map;

constexpr int kW = 640, kH = 480;

class Scratch {
public:
    explicit Scratch(const std::string& name)
        : m_path(std::filesystem::temp_directory_path() / ("navmap-" + name + "-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~Scratch() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    [[nodiscard]] std::filesystem::path operator/(const std::string& f) const { return m_path / f; }

private:
    std::filesystem::path m_path;
};

/// An SRTM3 tile N43E007.hgt of height(lat, lon) metres.
void writeHgt(const std::filesystem::path& path, const std::function<double(double, double)>& height) {
    std::vector<char> bytes(1201u * 1201u * 2u);
    for (int r = 0; r < 1201; ++r) {
        for (int c = 0; c < 1201; ++c) {
            const auto h = static_cast<std::int16_t>(std::lround(height(44.0 - r / 1200.0, 7.0 + c / 1200.0)));
            const std::size_t i = (static_cast<std::size_t>(r) * 1201 + c) * 2;
            bytes[i] = static_cast<char>((static_cast<std::uint16_t>(h) >> 8) & 0xff);
            bytes[i + 1] = static_cast<char>(static_cast<std::uint16_t>(h) & 0xff);
        }
    }
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Compiles `osm` (the body of an .osm file) with the DEM and returns the store's leaf tiles.
struct Compiled {
    std::shared_ptr<map::TileStore> store;
    std::vector<std::shared_ptr<const map::Tile>> leaves;
};
Compiled compile(const Scratch& dir, const std::string& osm_body, const std::function<double(double, double)>& height) {
    std::ofstream(dir / "in.osm") << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\">\n"
                                  << osm_body << "</osm>\n";
    writeHgt(dir / "N43E007.hgt", height);
    map::CompileOptions opt;
    opt.osm = dir / "in.osm";
    opt.dems = {dir / "N43E007.hgt"};
    opt.out = dir / "out.navmap";
    opt.leaf_tile_m = 1000;
    map::compileStore(opt);
    Compiled c;
    c.store = map::TileStore::open(opt.out);
    for (const auto& id : c.store->tileIds()) {
        if (id.level != c.store->scheme().leafLevel()) continue;
        auto res = c.store->load(id);
        EXPECT_TRUE(res.tile) << res.error;
        if (res.tile) c.leaves.push_back(res.tile);
    }
    return c;
}

struct Shot {
    Image image;
    Camera camera;
    MapFrameStats stats;
    glm::ivec2 pixel(glm::dvec3 world) const {
        const glm::mat4 vp = camera.projection(double(kW) / kH) * camera.viewRelativeTo(glm::dvec3(0.0));
        const glm::vec4 c = vp * glm::vec4(glm::vec3(world), 1.0f);
        return {static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kW),
                static_cast<int>((1.0f - (c.y / c.w * 0.5f + 0.5f)) * kH)};
    }
    glm::ivec3 at(glm::dvec3 world) const {
        const glm::ivec2 p = pixel(world);
        const auto* px = image.pixel(p.x, p.y);
        return {px[0], px[1], px[2]};
    }
};

Shot shoot(const std::vector<std::shared_ptr<const map::Tile>>& tiles, const Camera& camera, MapLayers layers = {},
           const MapStyle& style = MapStyle::day(), int frames = 1, const RouteGeometry* route = nullptr,
           bool hide_surface_labels = false) {
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    auto renderer = Renderer::create(o);
    renderer->setMapStyle(style);
    MapFrame frame;
    frame.camera = camera;
    frame.tiles = tiles;
    frame.layers = layers;
    frame.frame_dt_s = 0.25;
    frame.route = route;
    frame.hide_surface_labels = hide_surface_labels;
    for (int i = 0; i < frames; ++i) renderer->renderMap(frame);
    return {renderer->readSync(), camera, renderer->mapStats()};
}

glm::ivec3 to8(glm::vec3 c) { return glm::ivec3(glm::round(c * 255.0f)); }

bool near(glm::ivec3 a, glm::ivec3 b, int tol) {
    return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol && std::abs(a.z - b.z) <= tol;
}

/// A shade of `c` (relief shading scales the land cover): every channel the same multiple of c's.
bool shadeOf(glm::ivec3 px, glm::vec3 c, double tol = 0.08) {
    const glm::dvec3 k = glm::dvec3(px) / (glm::dvec3(c) * 255.0);
    return std::abs(k.x - k.y) <= tol && std::abs(k.y - k.z) <= tol && std::abs(k.x - k.z) <= tol && k.x > 0.4;
}

glm::dvec3 planar(const map::TileStore& store, double lat, double lon, double z) {
    const map::PlanarPoint p = store.projection().forward(lat, lon);
    return {p.x, p.y, z};
}

}  // namespace

// A coastline from the north-west to the south-east corner of the data: the water on its right
// (south-west), SRTM at 0 m everywhere (as over the sea). The sea point renders in the sea colour,
// not as the green hypsometric tint of a plain at 0 m; the land point does not.
TEST(MapDataRender, ASeaPointRendersInTheSeaColour) {
    const Scratch dir("sea-render");
    const Compiled c = compile(dir, R"(
 <node id="1" version="1" lat="43.040" lon="7.000"/>
 <node id="2" version="1" lat="43.020" lon="7.022"/>
 <node id="3" version="1" lat="43.000" lon="7.040"/>
 <node id="10" version="1" lat="43.034" lon="7.030"/>
 <node id="11" version="1" lat="43.036" lon="7.036"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><tag k="natural" v="coastline"/></way>
 <way id="200" version="1"><nd ref="10"/><nd ref="11"/><tag k="highway" v="residential"/></way>
)",
                               [](double, double) { return 0.0; });
    ASSERT_FALSE(c.leaves.empty());
    const glm::dvec3 sea = planar(*c.store, 43.012, 7.012, 0.0), land = planar(*c.store, 43.028, 7.028, 0.0);
    Camera cam;
    cam.eye = 0.5 * (sea + land) + glm::dvec3(0.0, -1.0, 3500.0);
    cam.target = 0.5 * (sea + land);
    cam.far_m = 20000.0;
    const Shot s = shoot(c.leaves, cam);
    // The land-cover raster holds 4 bits a channel (GpuTileCache).
    const glm::vec3 sea_color = glm::round(glm::vec3(landCoverColor(map::AreaClass::Sea)) * 15.0f) / 15.0f;
    EXPECT_TRUE(shadeOf(s.at(sea), sea_color))
        << "sea pixel " << s.at(sea).x << "," << s.at(sea).y << "," << s.at(sea).z;
    EXPECT_FALSE(shadeOf(s.at(land), sea_color))
        << "land pixel " << s.at(land).x << "," << s.at(land).y << "," << s.at(land).z;
    // The same at night, darker.
    const Shot n = shoot(c.leaves, cam, {}, MapStyle::night());
    EXPECT_TRUE(shadeOf(n.at(sea), sea_color))
        << "night sea pixel " << n.at(sea).x << "," << n.at(sea).y << "," << n.at(sea).z;
    EXPECT_LT(n.at(sea).z, s.at(sea).z);
}

// A lake with a marina multipolygon (leisure=marina, seamark:type=harbour) over its north-east
// part and a pier inside the marina (docs/tile-store.md "Area classes"). The marina is a tint over
// the water, never a park-green fill: its pixels are the water's colour a little deeper; the pier is
// drawn over both in its own colour.
TEST(MapDataRender, AMarinaTintsItsWaterAndAPierIsDrawnOverIt) {
    const Scratch dir("marina-render");
    const Compiled c = compile(dir, R"(
 <node id="1" version="1" lat="43.010" lon="7.010"/>
 <node id="2" version="1" lat="43.010" lon="7.036"/>
 <node id="3" version="1" lat="43.030" lon="7.036"/>
 <node id="4" version="1" lat="43.030" lon="7.010"/>
 <node id="11" version="1" lat="43.018" lon="7.018"/>
 <node id="12" version="1" lat="43.018" lon="7.034"/>
 <node id="13" version="1" lat="43.028" lon="7.034"/>
 <node id="14" version="1" lat="43.028" lon="7.018"/>
 <node id="21" version="1" lat="43.0233" lon="7.020"/>
 <node id="22" version="1" lat="43.0233" lon="7.032"/>
 <node id="23" version="1" lat="43.0247" lon="7.032"/>
 <node id="24" version="1" lat="43.0247" lon="7.020"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
  <tag k="natural" v="water"/><tag k="water" v="harbour"/></way>
 <way id="110" version="1"><nd ref="11"/><nd ref="12"/><nd ref="13"/><nd ref="14"/><nd ref="11"/></way>
 <way id="120" version="1"><nd ref="21"/><nd ref="22"/><nd ref="23"/><nd ref="24"/><nd ref="21"/>
  <tag k="man_made" v="pier"/></way>
 <relation id="1000" version="1"><member type="way" ref="110" role="outer"/>
  <tag k="type" v="multipolygon"/><tag k="leisure" v="marina"/><tag k="seamark:type" v="harbour"/></relation>
)",
                               [](double, double) { return 100.0; });
    ASSERT_FALSE(c.leaves.empty());
    const glm::dvec3 water = planar(*c.store, 43.013, 7.014, 100.0), marina = planar(*c.store, 43.020, 7.030, 100.0),
                     pier = planar(*c.store, 43.024, 7.027, 100.0);
    Camera cam;
    cam.target = planar(*c.store, 43.020, 7.023, 100.0);
    cam.eye = cam.target + glm::dvec3(0.0, -1.0, 3500.0);
    cam.far_m = 20000.0;
    MapLayers no_labels;
    no_labels.outlines = false;
    const Shot s = shoot(c.leaves, cam, no_labels);
    // The land-cover raster holds 4 bits a channel (GpuTileCache).
    auto raster = [](map::AreaClass cls) { return glm::round(glm::vec3(landCoverColor(cls)) * 15.0f) / 15.0f; };
    const glm::vec4 tint = landCoverColor(map::AreaClass::Harbour);
    const glm::vec3 tinted = glm::mix(raster(map::AreaClass::Water), glm::vec3(tint), tint.a);
    const glm::ivec3 w = s.at(water), m = s.at(marina), p = s.at(pier);
    auto str = [](glm::ivec3 v) { return std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z); };
    EXPECT_TRUE(shadeOf(w, raster(map::AreaClass::Water))) << "open water " << str(w);
    EXPECT_TRUE(shadeOf(m, tinted, 0.06)) << "marina " << str(m) << ", open water " << str(w);
    EXPECT_FALSE(shadeOf(m, raster(map::AreaClass::Park))) << "marina " << str(m);
    EXPECT_GT(m.z, m.x + 40) << "marina " << str(m);  // blue, as the water: not a green or grey fill
    EXPECT_GT(m.z, m.y + 20) << "marina " << str(m);
    EXPECT_LT(m.x, w.x - 8) << "marina " << str(m) << ", open water " << str(w);  // tinted, deeper
    EXPECT_LT(m.y, w.y - 8) << "marina " << str(m) << ", open water " << str(w);
    EXPECT_TRUE(shadeOf(p, raster(map::AreaClass::Pier), 0.05)) << "pier " << str(p);
    EXPECT_GT(p.x, w.x + 40) << "pier " << str(p) << ", open water " << str(w);  // over the water, not under it
}

// A named primary road in a tunnel (tunnel=yes, layer=-1) through a 400 m hill, and a named road
// in the open beside it. The tunnel is neither drawn on the hillside nor labelled; seen from
// inside the tunnel, the open road's label is left out too.
TEST(MapDataRender, ATunnelUnderAHillIsNotDrawnOrLabelledOnTheSurface) {
    const Scratch dir("tunnel-render");
    auto hill = [](double lat, double lon) {
        const double dy = (lat - 43.020) * 111320.0, dx = (lon - 7.020) * 81400.0;
        return 100.0 + 400.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * 500.0 * 500.0));
    };
    const Compiled c = compile(dir, R"(
 <node id="1" version="1" lat="43.020" lon="7.008"/>
 <node id="2" version="1" lat="43.020" lon="7.032"/>
 <node id="3" version="1" lat="43.0255" lon="7.008"/>
 <node id="4" version="1" lat="43.0255" lon="7.032"/>
 <node id="5" version="1" lat="43.010" lon="7.000"><tag k="place" v="hamlet"/><tag k="name" v="Foot"/></node>
 <node id="6" version="1" lat="43.035" lon="7.040"><tag k="place" v="hamlet"/><tag k="name" v="Top"/></node>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/><tag k="tunnel" v="yes"/>
  <tag k="layer" v="-1"/><tag k="name" v="Hill Tunnel"/></way>
 <way id="200" version="1"><nd ref="3"/><nd ref="4"/><tag k="highway" v="primary"/><tag k="name" v="Open Road"/></way>
)",
                               hill);
    ASSERT_FALSE(c.leaves.empty());
    Camera cam;
    cam.target = planar(*c.store, 43.0228, 7.020, 100.0);
    cam.eye = cam.target + glm::dvec3(0.0, -1.0, 2200.0);
    cam.far_m = 20000.0;
    MapLayers no_labels;
    no_labels.outlines = false;
    const Shot s = shoot(c.leaves, cam, no_labels);
    const glm::ivec3 fill = to8(MapStyle::day().roads.classes[static_cast<int>(map::RoadClass::Primary)].fill);
    auto road_pixels = [&](double lat, double lon) {
        const glm::ivec2 p = s.pixel(planar(*c.store, lat, lon, hill(lat, lon)));
        int n = 0;
        for (int y = p.y - 4; y <= p.y + 4; ++y) {
            for (int x = p.x - 4; x <= p.x + 4; ++x) {
                const auto* px = s.image.pixel(x, y);
                n += near({px[0], px[1], px[2]}, fill, 12) ? 1 : 0;
            }
        }
        return n;
    };
    for (double lon : {7.014, 7.017, 7.020, 7.023, 7.026}) {
        EXPECT_EQ(road_pixels(43.020, lon), 0) << "tunnel drawn on the hillside at lon " << lon;
        EXPECT_GT(road_pixels(43.0255, lon), 0) << "the open road is missing at lon " << lon;
    }
    MapLayers labels;
    labels.labels = true;
    const Shot l = shoot(c.leaves, cam, labels, MapStyle::day(), 8);
    bool open_road = false;
    for (const auto& d : l.stats.drawn_labels) {
        EXPECT_NE(d.text, "Hill Tunnel");
        open_road = open_road || d.text == "Open Road";
    }
    EXPECT_TRUE(open_road) << l.stats.drawn_labels.size() << " labels drawn, none of them the open road's";
    // Inside the tunnel (MapFrame::hide_surface_labels) the surface's labels are left out: the
    // frame is the one drawn with the labels off, to the pixel.
    const Shot inside = shoot(c.leaves, cam, labels, MapStyle::day(), 8, nullptr, true);
    EXPECT_TRUE(inside.stats.drawn_labels.empty()) << inside.stats.drawn_labels.size() << " labels drawn";
    MapLayers labels_off = labels;
    labels_off.labels = false;
    const Shot off = shoot(c.leaves, cam, labels_off, MapStyle::day(), 8);
    EXPECT_NE(l.image.rgba, off.image.rgba) << "the labels draw nothing here";
    EXPECT_EQ(inside.image.rgba, off.image.rgba);
}

// A route through the tunnel under the hill: in the tunnel it is drawn dashed on the hillside
// above (on and off runs along its centre line), before and after it solid. Without the tunnel
// in its geometry the same stretch is solid.
TEST(MapDataRender, ARouteThroughATunnelIsDrawnDashedOnTheHillAbove) {
    const Scratch dir("tunnel-route");
    auto hill = [](double lat, double lon) {
        const double dy = (lat - 43.020) * 111320.0, dx = (lon - 7.020) * 81400.0;
        return 100.0 + 400.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * 500.0 * 500.0));
    };
    const Compiled c = compile(dir, R"(
 <node id="1" version="1" lat="43.020" lon="7.008"/>
 <node id="2" version="1" lat="43.020" lon="7.032"/>
 <node id="3" version="1" lat="43.020" lon="7.002"/>
 <node id="4" version="1" lat="43.020" lon="7.038"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/><tag k="tunnel" v="yes"/>
  <tag k="layer" v="-1"/></way>
 <way id="101" version="1"><nd ref="3"/><nd ref="1"/><tag k="highway" v="primary"/></way>
 <way id="102" version="1"><nd ref="2"/><nd ref="4"/><tag k="highway" v="primary"/></way>
)",
                               hill);
    ASSERT_FALSE(c.leaves.empty());
    // The route along the three ways, west to east, a point every 10 m.
    RouteGeometry route;
    const glm::dvec3 west = planar(*c.store, 43.020, 7.002, 0.0), east = planar(*c.store, 43.020, 7.038, 0.0);
    const double length = glm::length(east - west);
    for (double m = 0.0; m <= length; m += 10.0) {
        route.points.push_back(west + (east - west) * (m / length));
        route.measure_m.push_back(m);
    }
    route.version = 1;
    const double portal_w = glm::length(planar(*c.store, 43.020, 7.008, 0.0) - west);
    const double portal_e = glm::length(planar(*c.store, 43.020, 7.032, 0.0) - west);
    Camera cam;
    cam.target = planar(*c.store, 43.0205, 7.020, 100.0);
    cam.eye = cam.target + glm::dvec3(0.0, -1.0, 2600.0);
    cam.far_m = 20000.0;
    MapLayers layers;
    layers.outlines = false;
    layers.roads = false;  // only the route is blue
    const glm::ivec3 blue = to8(MapStyle::day().route_color);
    // Along the route's centre line between two distances: pixels of the route's fill, and
    // runs of them (a run ends at a pixel that is not).
    struct Line {
        int on = 0, off = 0, runs = 0;
    };
    auto along = [&](const Shot& s, double from_m, double to_m) {
        Line l;
        glm::ivec2 last(-1);
        bool was_on = false;
        for (double m = from_m; m <= to_m; m += 1.0) {
            const glm::dvec3 p = west + (east - west) * (m / length);
            double lat = 0.0, lon = 0.0;
            c.store->projection().reverse({p.x, p.y}, lat, lon);
            const glm::ivec2 q = s.pixel({p.x, p.y, hill(lat, lon)});
            if (q == last) continue;
            last = q;
            const auto* px = s.image.pixel(q.x, q.y);
            const bool on = near({px[0], px[1], px[2]}, blue, 16);
            (on ? l.on : l.off) += 1;
            l.runs += on && !was_on ? 1 : 0;
            was_on = on;
        }
        return l;
    };
    const Shot solid = shoot(c.leaves, cam, layers, MapStyle::day(), 1, &route);
    route.tunnels_m = {{portal_w, portal_e}};
    route.version = 2;
    const Shot dashed = shoot(c.leaves, cam, layers, MapStyle::day(), 1, &route);
    const Line before = along(dashed, 40.0, portal_w - 40.0), after = along(dashed, portal_e + 40.0, length - 40.0);
    const Line inside = along(dashed, portal_w + 40.0, portal_e - 40.0);
    const Line inside_solid = along(solid, portal_w + 40.0, portal_e - 40.0);
    std::printf("[ measured ] route centre line in the tunnel: %d on, %d off, %d runs (solid without: %d on, %d off)\n",
                inside.on, inside.off, inside.runs, inside_solid.on, inside_solid.off);
    EXPECT_EQ(before.off, 0) << before.on << " route pixels before the tunnel";
    EXPECT_EQ(after.off, 0) << after.on << " route pixels after the tunnel";
    EXPECT_GT(before.on, 20);
    EXPECT_EQ(inside_solid.off, 0) << "without the tunnel: " << inside_solid.on << " route pixels";
    // Dashes and gaps of two route widths each: half on (measured 221 of 432 pixels), and many
    // runs (measured 52 over 1.9 km).
    EXPECT_GE(inside.runs, 20) << inside.on << " on, " << inside.off << " off";
    EXPECT_NEAR(inside.on, inside.off, (inside.on + inside.off) / 8) << "dashes and gaps of one length";
}

// A flat 1 km store seen from its east edge, looking outward: beyond the data the ground goes on
// to the horizon (also past the camera's far plane), in the far-ground colour; the sky stays above.
TEST(MapDataRender, BeyondTheStoresEdgeTheGroundContinuesBelowTheHorizon) {
    std::shared_ptr<map::Tile> tile = navmap::test::makeTile([](float, float) { return 500.0f; });
    const glm::dvec3 o(tile->origin_x, tile->origin_y, 0.0);
    Camera cam;
    cam.eye = o + glm::dvec3(1000.0, 500.0, 800.0);
    cam.target = o + glm::dvec3(3000.0, 500.0, 500.0);
    cam.far_m = 5000.0;
    for (const MapStyle& style : {MapStyle::day(), MapStyle::night()}) {
        const Shot s = shoot({tile}, cam, {}, style);
        const glm::ivec3 sky = to8(style.sky_color), ground = to8(style.far_ground_color * style.brightness);
        for (double x : {1500.0, 2500.0, 4000.0, 9000.0}) {  // 9 km: beyond the far plane
            const glm::ivec3 px = s.at(o + glm::dvec3(x, 500.0, 500.0));
            EXPECT_FALSE(near(px, sky, 10)) << "clear colour below the horizon at x " << x;
            EXPECT_TRUE(near(px, ground, 12)) << "x " << x << ": " << px.x << "," << px.y << "," << px.z;
        }
        const glm::ivec3 above = s.at(o + glm::dvec3(3000.0, 500.0, 1000.0));  // above the horizon
        EXPECT_TRUE(near(above, sky, 3)) << above.x << "," << above.y << "," << above.z;
    }
    // Without it (MapLayers::far_ground off) the clear colour shows there.
    MapLayers without;
    without.far_ground = false;
    const Shot bare = shoot({tile}, cam, without);
    EXPECT_TRUE(near(bare.at(o + glm::dvec3(2500.0, 500.0, 500.0)), to8(MapStyle::day().sky_color), 3));
}

// OSM layers stack the roads where they cross (docs/rendering.md "Tunnels and layers"): a
// residential road at layer=1 over a primary one at layer 0, though the primary is the more
// important class, which wins a crossing within one layer; and a secondary bridge at layer=2 over
// a primary bridge at layer=1.
TEST(MapDataRender, RoadsAndBridgesCrossInTheOrderOfTheirLayers) {
    const Scratch dir("layer-render");
    const Compiled c = compile(dir, R"(
 <node id="1" version="1" lat="43.010" lon="7.000"/>
 <node id="2" version="1" lat="43.010" lon="7.020"/>
 <node id="3" version="1" lat="43.004" lon="7.006"/>
 <node id="4" version="1" lat="43.016" lon="7.006"/>
 <node id="5" version="1" lat="43.025" lon="7.000"/>
 <node id="6" version="1" lat="43.025" lon="7.020"/>
 <node id="7" version="1" lat="43.019" lon="7.006"/>
 <node id="8" version="1" lat="43.031" lon="7.006"/>
 <way id="100" version="1"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/></way>
 <way id="200" version="1"><nd ref="3"/><nd ref="4"/><tag k="highway" v="residential"/><tag k="layer" v="1"/></way>
 <way id="300" version="1"><nd ref="5"/><nd ref="6"/><tag k="highway" v="primary"/><tag k="bridge" v="yes"/>
  <tag k="layer" v="1"/></way>
 <way id="400" version="1"><nd ref="7"/><nd ref="8"/><tag k="highway" v="secondary"/><tag k="bridge" v="yes"/>
  <tag k="layer" v="2"/></way>
)",
                               [](double, double) { return 200.0; });
    ASSERT_FALSE(c.leaves.empty());
    // Both crossings lie 170 m and more from the borders of the 1 km leaf tiles, whose order on
    // screen is nearest first, not by layer.
    const glm::dvec3 ground_crossing = planar(*c.store, 43.010, 7.006, 200.0);
    const glm::dvec3 bridge_crossing = planar(*c.store, 43.025, 7.006, 200.0);
    MapLayers layers;
    layers.outlines = false;
    const RoadStyle& roads = MapStyle::day().roads;
    auto fill = [&](map::RoadClass cls) { return to8(roads.classes[static_cast<int>(cls)].fill); };
    ASSERT_FALSE(near(fill(map::RoadClass::Residential), fill(map::RoadClass::Primary), 12));
    ASSERT_FALSE(near(fill(map::RoadClass::Secondary), fill(map::RoadClass::Primary), 12));
    for (const glm::dvec3& crossing : {ground_crossing, bridge_crossing}) {
        Camera cam;
        cam.target = crossing;
        cam.eye = crossing + glm::dvec3(0.0, -1.0, 600.0);
        cam.far_m = 20000.0;
        const Shot s = shoot(c.leaves, cam, layers);
        const glm::ivec3 top =
            crossing == ground_crossing ? fill(map::RoadClass::Residential) : fill(map::RoadClass::Secondary);
        const glm::ivec3 px = s.at(crossing);
        EXPECT_TRUE(near(px, top, 12)) << (crossing == ground_crossing ? "ground" : "bridge") << " crossing: " << px.x
                                       << "," << px.y << "," << px.z << ", expected " << top.x << "," << top.y << ","
                                       << top.z;
    }
}
