// SPDX-License-Identifier: Apache-2.0
#pragma once
// The terrain-only scene built straight from a DEM file: the first real scene (the shaded
// heightfield of Andorra) and the baseline that later layers are measured against.

#include <filesystem>

#include "navmap/map/dem.h"
#include "navmap/map/projection.h"
#include "navmap/render/camera.h"
#include "navmap/render/heightfield.h"

namespace navmap::render {

/// A geographic rectangle in degrees.
struct GeoBox {
    double south, west, north, east;
};

/// Andorra with a margin of surrounding Pyrenees (the embedded default data).
inline constexpr GeoBox kAndorraBox{42.40, 1.38, 42.68, 1.82};

struct TerrainScene {
    map::Projection projection;
    HeightfieldMesh mesh;
    std::size_t voids_filled = 0;
};

/// Loads an SRTM tile, fills its voids, crops it to `box` and builds the mesh in a projection
/// centred on the box. Throws map::DemError naming the file when it cannot be read.
TerrainScene loadTerrainScene(const std::filesystem::path& hgt, const GeoBox& box = kAndorraBox);

/// A fixed overview camera: from the south-west above the Gran Valira towards Andorra la Vella
/// and the high valleys (used by the golden test and the benchmark).
Camera andorraOverviewCamera(const map::Projection& projection);

/// A point of the demo fly-over: an orbit around the centre of the country, t in [0, 1).
Camera andorraFlyoverCamera(const map::Projection& projection, double t);

}  // namespace navmap::render
