#pragma once
// Level-of-detail selection over the tile quadtree: a tile is refined into its children while
// its geometric error (the DEM spacing of its level) projects to more than max_error_px on
// screen; tiles outside the view frustum are skipped. Children that are not resident yet are
// requested and their parent is drawn meanwhile, so nothing blocks and nothing is missing.

#include <functional>
#include <memory>
#include <vector>

#include "navmap/map/tile.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_scheme.h"
#include "navmap/render/camera.h"

namespace navmap::render {

struct LodOptions {
    double max_error_px = 3.0;  ///< screen-space error threshold
    int dem_samples = 65;       ///< DEM samples per tile side (store info)
    /// Vertical error of a level as a fraction of its sample spacing: halving the resolution of
    /// SRTM-like terrain moves the surface by about a tenth of the spacing on average.
    double error_per_spacing = 0.1;
    double min_height_m = -500.0;  ///< vertical extent assumed for culling
    double max_height_m = 5000.0;
};

struct LodSelection {
    std::vector<std::shared_ptr<const map::Tile>> draw;  ///< non-overlapping, coarse where needed
    std::vector<map::TileRequest> wanted;               ///< tiles to load (visible first)
    int finest_level = 0;
    std::size_t culled = 0;
};

/// `exists(id)`: the store has this tile. `resident(id)`: the loaded tile or null.
LodSelection selectLod(const map::TileScheme& scheme, const Camera& camera, double aspect, int viewport_height,
                       const std::function<bool(map::TileId)>& exists,
                       const std::function<std::shared_ptr<const map::Tile>(map::TileId)>& resident,
                       const LodOptions& options = {});

/// Projected size in pixels of a geometric error of error_m seen at distance_m.
double screenSpaceError(double error_m, double distance_m, double fov_y_deg, int viewport_height);

}  // namespace navmap::render
