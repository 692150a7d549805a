// SPDX-License-Identifier: Apache-2.0
// The world tile scheme (world_tiles.h) and the local frames on it (projection.h): address round
// trips, neighbours across the antimeridian, the frames' scale and conformality, and the precision
// of a tile's float vertices drawn in a frame around the camera, at the equator and at 70 N.

#include <gtest/gtest.h>
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <random>

#include "navmap/map/projection.h"
#include "navmap/map/tile_codec.h"
#include "navmap/map/tile_scheme.h"
#include "navmap/map/world_tiles.h"

using namespace navmap::map;

namespace {

double geodesicM(double lat1, double lon1, double lat2, double lon2) {
    double s12 = 0;
    GeographicLib::Geodesic::WGS84().Inverse(lat1, lon1, lat2, lon2, s12);
    return s12;
}

}  // namespace

TEST(WorldTiles, AddressesRoundTripThroughKeysTextAndPositions) {
    std::mt19937_64 rng(7);
    for (int z = 0; z <= kMaxWorldZoom; ++z) {
        for (int i = 0; i < 50; ++i) {
            const std::uint64_t n = std::uint64_t{1} << z;
            const WorldTileId id{z, static_cast<std::uint32_t>(rng() % n), static_cast<std::uint32_t>(rng() % n)};
            ASSERT_TRUE(id.valid());
            EXPECT_EQ(WorldTileId::fromKey(id.key()), id) << id.toString();
            EXPECT_EQ(WorldTileId::parse(id.toString()), id);
            // The tile holding its own centre, found from lat/lon (z <= 24: below that a tile is
            // under 3 m and lat/lon doubles still resolve it, but keep the check meaningful).
            if (z <= 24) {
                double lat = 0, lon = 0;
                fromWorldMercator(id.centre(), lat, lon);
                EXPECT_EQ(worldTileAt(z, lat, lon), id) << id.toString();
            }
            if (z > 0) {
                EXPECT_TRUE(id.parent().contains(id));
                EXPECT_EQ(id.parent().child(static_cast<int>((id.x & 1u) | ((id.y & 1u) << 1))), id);
            }
        }
    }
    // Keys are distinct across levels: 0/0/0 and 1/0/0 differ.
    EXPECT_NE((WorldTileId{0, 0, 0}.key()), (WorldTileId{1, 0, 0}.key()));
    EXPECT_EQ((WorldTileId{0, 0, 0}.key()), 1u);
    EXPECT_FALSE(WorldTileId::fromKey(0));
    EXPECT_FALSE(WorldTileId::fromKey(2));      // the marker bit at an odd position
    EXPECT_FALSE(WorldTileId::parse("3/8/0"));  // x outside level 3
    EXPECT_FALSE(WorldTileId::parse("3/1/1/"));
    EXPECT_FALSE(WorldTileId::parse("31/0/0"));
    EXPECT_FALSE(WorldTileId::parse("a/1/1"));
    EXPECT_FALSE(WorldTileId::parse(""));
}

TEST(WorldTiles, NeighboursWrapAtTheAntimeridianAndStopAtThePoles) {
    const int z = 14;
    const std::uint32_t last = (1u << z) - 1;
    const WorldTileId west_edge = worldTileAt(z, 65.0, -179.999);
    const WorldTileId east_edge = worldTileAt(z, 65.0, 179.999);
    EXPECT_EQ(west_edge.x, 0u);
    EXPECT_EQ(east_edge.x, last);
    EXPECT_EQ(west_edge.y, east_edge.y);
    EXPECT_EQ(east_edge.neighbour(1, 0), west_edge);
    EXPECT_EQ(west_edge.neighbour(-1, 0), east_edge);
    EXPECT_EQ(west_edge.neighbour(-3, 1), (WorldTileId{z, last - 2, west_edge.y + 1}));
    EXPECT_EQ((WorldTileId{z, 5, 7}.neighbour(static_cast<int>(1u << z), 0)), (WorldTileId{z, 5, 7}));  // once round
    EXPECT_FALSE((WorldTileId{z, 5, 0}.neighbour(0, -1)));
    EXPECT_FALSE((WorldTileId{z, 5, last}.neighbour(0, 1)));
    EXPECT_FALSE((WorldTileId{0, 0, 0}.neighbour(0, 1)));
    EXPECT_EQ((WorldTileId{0, 0, 0}.neighbour(1, 0)), (WorldTileId{0, 0, 0}));

    // The tiles either side of the antimeridian touch in a frame there: the east edge of one is
    // the west edge of the other, metres apart on the ground, not a world apart.
    const Projection frame(65.0, 180.0);
    const PlanarPoint a = frame.fromMercator({east_edge.southWest().x + east_edge.size(), east_edge.southWest().y});
    const PlanarPoint b = frame.fromMercator(west_edge.southWest());
    EXPECT_NEAR(a.x, b.x, 1e-6);
    EXPECT_NEAR(a.y, b.y, 1e-6);
    const PlanarPoint w = frame.forward(65.0, 179.99), e = frame.forward(65.0, -179.99);
    EXPECT_NEAR(e.x - w.x, geodesicM(65.0, 179.99, 65.0, -179.99), 1e-3);
    double lat = 0, lon = 0;
    frame.reverse(e, lat, lon);
    EXPECT_NEAR(lon, -179.99, 1e-9);
}

TEST(WorldTiles, TheWorldSquareEndsAtTheLatitudeLimit) {
    EXPECT_NEAR(worldLatitudeLimit(), 85.0840, 1e-4);
    const MercatorPoint top = toWorldMercator(worldLatitudeLimit(), 0.0);
    EXPECT_NEAR(top.y, worldHalfSize(), 1e-6);
    EXPECT_EQ(worldTileAt(3, 89.0, 10.0), (WorldTileId{3, 4, 7}));  // clamped into the top row
    EXPECT_EQ(worldTileAt(3, -89.0, -10.0), (WorldTileId{3, 3, 0}));
}

TEST(LocalFrame, IsTrueToScaleAndConformalAtItsOriginAnywhere) {
    for (const double lat : {0.0, 42.5, 70.0, -55.0}) {
        const Projection frame(lat, 20.0);
        const PlanarPoint o = frame.forward(lat, 20.0);
        EXPECT_NEAR(o.x, 0.0, 1e-9);
        EXPECT_NEAR(o.y, 0.0, 1e-9);
        // 10 m east and 10 m north of the origin, against the geodesic: the same scale both ways
        // (north, the scale's drift over the 10 m: tan(lat) * 5 m / R).
        const double d = 1e-4;  // degrees
        const PlanarPoint e = frame.forward(lat, 20.0 + d), n = frame.forward(lat + d, 20.0);
        EXPECT_NEAR(e.x / geodesicM(lat, 20.0, lat, 20.0 + d), 1.0, 1e-8) << lat;
        EXPECT_NEAR(n.y / geodesicM(lat, 20.0, lat + d, 20.0), 1.0 + std::tan(lat * M_PI / 180) * 5.5 / 6378137.0, 3e-8)
            << lat;
        EXPECT_NEAR(e.y, 0.0, 1e-9);
        EXPECT_NEAR(n.x, 0.0, 1e-9);
        double back_lat = 0, back_lon = 0;
        frame.reverse(frame.forward(lat + 0.3, 20.7), back_lat, back_lon);
        EXPECT_NEAR(back_lat, lat + 0.3, 1e-10);
        EXPECT_NEAR(back_lon, 20.7, 1e-10);
    }
    // Away from the origin the scale drifts with latitude only: tan(lat) / R per metre north.
    const Projection frame(70.0, 20.0);
    const double d = 1e-4;
    const PlanarPoint a = frame.forward(70.09, 20.0), b = frame.forward(70.09 + d, 20.0);
    const double drift = (b.y - a.y) / geodesicM(70.09, 20.0, 70.09 + d, 20.0) - 1.0;
    EXPECT_NEAR(drift, std::tan(70.0 * M_PI / 180) * 10000.0 / 6378137.0, 5e-5);  // 10 km north: +0.43 %
}

TEST(LocalFrame, FramesDifferByAScaleAndATranslation) {
    const Projection andorra(42.55, 1.55), north(49.5, 6.5);  // about 800 km apart
    const FrameTransform t = north.transformFrom(andorra);
    EXPECT_NEAR(t.scale, worldMercatorScale(42.55) / worldMercatorScale(49.5), 1e-15);
    EXPECT_LT(t.scale, 1.0);  // a metre at 42.55 N is less than one of 49.5 N's frame metres
    for (const auto& [lat, lon] : {std::pair{42.5, 1.5}, {42.7, 1.8}, {49.5, 6.5}, {45.0, 3.0}}) {
        const PlanarPoint a = andorra.forward(lat, lon);
        const PlanarPoint n = north.forward(lat, lon);
        EXPECT_NEAR(t.scale * a.x + t.offset_x, n.x, 1e-6);
        EXPECT_NEAR(t.scale * a.y + t.offset_y, n.y, 1e-6);
    }
    EXPECT_TRUE(andorra.transformFrom(Projection(42.55, 1.55)).identity());
}

TEST(StoreScheme, IsASubtreeOfTheWorldScheme) {
    const Projection frame(42.55, 1.55);
    const TileScheme s = TileScheme::forData(frame, 42.42, 1.40, 42.66, 1.79, 2000.0);
    // 2 km leaves at 42.55 N: World Mercator level 14, 1.80 km on the ground.
    EXPECT_EQ(s.worldTile({static_cast<std::uint8_t>(s.leafLevel()), 0, 0}).z, 14);
    EXPECT_NEAR(s.tileSize(s.leafLevel()), 1804.7, 0.1);
    const WorldTileId root = s.worldRoot();
    EXPECT_TRUE(root.contains(worldTileAt(14, 42.42, 1.40)));
    EXPECT_TRUE(root.contains(worldTileAt(14, 42.66, 1.79)));
    EXPECT_FALSE(root.child(0).contains(worldTileAt(14, 42.42, 1.40)) &&
                 root.child(0).contains(worldTileAt(14, 42.66, 1.79)));  // the finest one
    for (int level = 0; level < s.levelCount(); ++level) {
        const auto id = s.tileAt(level, frame.forward(42.5075, 1.5218));
        ASSERT_TRUE(id);
        const WorldTileId w = s.worldTile(*id);
        EXPECT_EQ(w, worldTileAt(root.z + level, 42.5075, 1.5218));
        EXPECT_EQ(s.fromWorld(w), id);
        // The store tile's square is the world tile's square in the frame.
        const Box b = s.bounds(*id);
        const PlanarPoint sw = frame.fromMercator(w.southWest());
        EXPECT_NEAR(b.min_x, sw.x, 1e-6);
        EXPECT_NEAR(b.min_y, sw.y, 1e-6);
        EXPECT_NEAR(b.max_x - b.min_x, w.size() / frame.scale(), 1e-6);
    }
    EXPECT_FALSE(s.fromWorld(worldTileAt(14, 48.0, 7.0)));  // outside the subtree
    EXPECT_FALSE(s.fromWorld(root.parent()));               // above the root
}

namespace {

/// The error, in metres, of drawing points of a leaf tile the way the renderer does: the store
/// keeps a tile's vertices as floats relative to its corner, quantised by the codec; the frame
/// around the camera gets the tile's corner in double, subtracts the eye in double, and does the
/// rest in float (scale, add), as the vertex shader does with a camera-relative view matrix.
double worstDrawnErrorM(double lat, double lon, double eye_north_m) {
    const Projection store(lat + 0.2, lon - 0.3);  // the store's frame, centred elsewhere
    const WorldTileId tile = worldTileAt(16, lat, lon);
    const PlanarPoint corner = store.fromMercator(tile.southWest());
    const Projection camera(lat, lon);
    const PlanarPoint eye{0.0, eye_north_m};  // the eye in the camera frame
    const FrameTransform t = camera.transformFrom(store);
    const double corner_x = t.scale * corner.x + t.offset_x - eye.x;  // double, as viewRelativeTo
    const double corner_y = t.scale * corner.y + t.offset_y - eye.y;
    double worst = 0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const MercatorPoint m{tile.southWest().x + u(rng) * tile.size(), tile.southWest().y + u(rng) * tile.size()};
        double plat = 0, plon = 0;
        fromWorldMercator(m, plat, plon);
        const PlanarPoint s = store.forward(plat, plon);
        // The codec's centimetre quantum, then float.
        const auto local_x = static_cast<float>(std::round((s.x - corner.x) / kCoordQuantum) * kCoordQuantum);
        const auto local_y = static_cast<float>(std::round((s.y - corner.y) / kCoordQuantum) * kCoordQuantum);
        const float drawn_x = static_cast<float>(corner_x) + static_cast<float>(t.scale) * local_x;
        const float drawn_y = static_cast<float>(corner_y) + static_cast<float>(t.scale) * local_y;
        const PlanarPoint truth = camera.forward(plat, plon);
        worst = std::max(worst, std::hypot(drawn_x - (truth.x - eye.x), drawn_y - (truth.y - eye.y)));
    }
    return worst;
}

}  // namespace

TEST(LocalFrame, ATileIsDrawnWithSubCentimetreErrorAtTheEquatorAndAt70North) {
    // The camera above the tile (the eye 100 m south of the frame's origin) ...
    EXPECT_LT(worstDrawnErrorM(0.01, 10.0, -100.0), 0.01);
    EXPECT_LT(worstDrawnErrorM(70.0, 25.0, -100.0), 0.01);
    EXPECT_LT(worstDrawnErrorM(-33.9, 151.2, -100.0), 0.01);
    // ... and the same tile seen from 300 km away: float's step at 300 km is 3 cm; the error
    // stays below it (1e-7 of the distance, far below a pixel).
    EXPECT_LT(worstDrawnErrorM(70.0, 25.0, -300000.0), 0.04);
    EXPECT_LT(worstDrawnErrorM(0.01, 10.0, -300000.0), 0.04);
}
