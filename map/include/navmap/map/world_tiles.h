// SPDX-License-Identifier: Apache-2.0
#pragma once
// The world tile scheme: one quadtree over the whole Earth in the ellipsoidal Mercator
// projection of WGS84 (EPSG:3395, "World Mercator"), shared by every store and every daemon.
//
// - World Mercator: X = a * longitude (radians), Y = a * isometric latitude of the ellipsoid, a the
//   WGS84 semi-major axis. Conformal on the ellipsoid (shapes are exact; the scale is
//   k(lat) = sqrt(1 - e^2 sin^2 lat) / cos lat in both directions), and its grid north is true
//   north everywhere. The world is the square [-pi a, pi a]^2 (latitudes within about +-85.08 deg).
// - Level z has 2^z x 2^z tiles; x grows east from the antimeridian, y grows north from the
//   square's south edge (so a tile's children and the stores' own level/x/y grow the same way).
// - A local frame (`navmap::map::Projection`) is World Mercator around an origin, divided by the
//   scale at the origin: metres east and north, true to scale at the origin. Any two local frames
//   differ by a uniform scale and a translation only (`FrameTransform`), so a tile square in one
//   frame is an axis-aligned square in every other: tiles from different stores meet without
//   cracks.
// Why this scheme and not a geodetic one like NDS's: docs/tile-store.md "World tile scheme".

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace navmap::map {

/// The world square's half width in World Mercator metres (pi times the WGS84 semi-major axis).
[[nodiscard]] double worldHalfSize();
/// Largest |latitude| inside the world square (about 85.08 degrees).
[[nodiscard]] double worldLatitudeLimit();

/// World Mercator coordinates in metres (equatorial scale).
struct MercatorPoint {
    double x = 0.0;
    double y = 0.0;
};

/// lat/lon (degrees) to World Mercator; longitudes are taken modulo 360 into [-180, 180).
[[nodiscard]] MercatorPoint toWorldMercator(double lat_deg, double lon_deg);
/// The inverse; longitude in [-180, 180).
void fromWorldMercator(MercatorPoint m, double& lat_deg, double& lon_deg);
/// The projection's scale at a latitude: World Mercator metres per ground metre.
[[nodiscard]] double worldMercatorScale(double lat_deg);

inline constexpr int kMaxWorldZoom = 30;

/// A tile of the world quadtree.
struct WorldTileId {
    int z = 0;
    std::uint32_t x = 0;  ///< 0 at the antimeridian, growing east
    std::uint32_t y = 0;  ///< 0 at the south edge, growing north

    friend bool operator==(const WorldTileId&, const WorldTileId&) = default;
    [[nodiscard]] bool valid() const;
    /// One 64-bit number per tile of every level (a 1 bit above the interleaved x/y bits, as a
    /// quadkey with a leading marker): distinct tiles give distinct keys; fromKey() inverts it.
    [[nodiscard]] std::uint64_t key() const;
    [[nodiscard]] static std::optional<WorldTileId> fromKey(std::uint64_t key);
    /// "z/x/y".
    [[nodiscard]] std::string toString() const;
    /// Parses "z/x/y"; nullopt for anything else or a tile outside its level.
    [[nodiscard]] static std::optional<WorldTileId> parse(std::string_view text);

    [[nodiscard]] WorldTileId parent() const;
    /// Child 0..3: bit 0 east, bit 1 north.
    [[nodiscard]] WorldTileId child(int which) const;
    [[nodiscard]] bool contains(const WorldTileId& descendant) const;
    /// The tile dx columns east and dy rows north. Columns wrap at the antimeridian (the
    /// world is a cylinder); rows do not: nullopt beyond the south or north edge.
    [[nodiscard]] std::optional<WorldTileId> neighbour(int dx, int dy) const;

    /// The tile's square in World Mercator.
    [[nodiscard]] double size() const;
    [[nodiscard]] MercatorPoint southWest() const;
    [[nodiscard]] MercatorPoint centre() const;
};

/// The tile of level z holding a World Mercator point (clamped to the world square).
[[nodiscard]] WorldTileId worldTileAt(int z, MercatorPoint m);
[[nodiscard]] WorldTileId worldTileAt(int z, double lat_deg, double lon_deg);
/// The finest level z <= max_z whose one tile holds both corners of a lat/lon box.
[[nodiscard]] WorldTileId worldTileCovering(double south, double west, double north, double east, int max_z);
/// The level whose tiles are closest (in a power of two) to size_m ground metres at lat_deg.
[[nodiscard]] int worldZoomForGroundSize(double size_m, double lat_deg);

/// p_to = scale * p_from + offset: a point of one local frame (navmap::map::Projection) in
/// another. Heights are not scaled: both frames measure them in metres.
struct FrameTransform {
    double scale = 1.0;
    double offset_x = 0.0, offset_y = 0.0;
    [[nodiscard]] bool identity() const { return scale == 1.0 && offset_x == 0.0 && offset_y == 0.0; }
};

}  // namespace navmap::map
