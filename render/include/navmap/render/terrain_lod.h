// SPDX-License-Identifier: Apache-2.0
#pragma once
// Level-of-detail selection over the tile quadtree: a tile is refined into its children while
// its geometric error (the DEM spacing of its level) projects to more than max_error_px on
// screen; tiles outside the view frustum are skipped. Children that are not resident yet are
// requested and their parent is drawn meanwhile, so nothing blocks and nothing is missing.
//
// Geomorphing (CDLOD, Strugar 2009; so a level switch does not pop). A tile of level L >= 1 is drawn
// only while its parent's box is nearer than end(L) = refineDistance(L - 1), the distance where
// the parent's screen-space error reaches max_error_px. Each vertex blends with the factor
//     f_L(d) = clamp((d - start(L)) / (end(L) - start(L)), 0, 1),  start(L) = morph_start * end(L),
// where d is its distance to the camera measured like the selection measures tile boxes
// (horizontal distance, plus the camera's height above/below the LOD height band). Tiles are
// large against these distances (with 65 samples per tile and 3 px, end(L) is 0.15-0.45 of the
// parent's edge for 240-720 px high views), so one tile spans several morph ranges; a vertex
// therefore carries the surfaces of kMorphLevels ancestor levels h_L-1 .. h_L-4 (each the
// ancestor's triangulated surface at the vertex) and shows
//     S_L(d) = mix(h_L, S_L-1(d), f_L(d)),   S_L-4(d) = h_L-4,
// a function of d alone for every tile drawn there. When the parent box crosses end(L) every
// vertex of the tile is at d >= end(L) where f_L = 1 and S_L = S_L-1: exactly what the parent
// draws, so the switch (and the switch back) changes nothing on screen. Skirt vertices share
// their border vertex's x, y and hence its factors, so the skirts stay attached while morphing.
// The land-cover rasters of the parent and grandparent blend in with the same factors
// (shaders/terrain_tile.frag). What remains at a switch is per-vertex relief shading on ridges (a
// finer mesh samples the shading of the same surface at more points).

#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "navmap/map/tile.h"
#include "navmap/map/tile_cache.h"
#include "navmap/map/tile_scheme.h"
#include "navmap/render/camera.h"
#include "navmap/render/map_frame.h"

namespace navmap::render {

struct LodOptions {
    double max_error_px = 3.0;  ///< screen-space error threshold
    int dem_samples = 65;       ///< DEM samples per tile side (store info)
    /// Vertical error of a level as a fraction of its sample spacing: halving the resolution of
    /// SRTM-like terrain moves the surface by about a tenth of the spacing on average.
    double error_per_spacing = 0.1;
    double min_height_m = -500.0;  ///< vertical extent assumed for culling
    double max_height_m = 5000.0;
    /// The morph towards the parent level starts at this fraction of the distance where it must
    /// be complete (CDLOD's morph start ratio). Above 0.5: a tile is drawn from
    /// refineDistance(L) = end / 2 outwards, so its nearest vertices never morph.
    double morph_start = 0.7;
    bool morph = true;  ///< fill LodSelection::morph (false: tiles switch level abruptly)
};

struct LodSelection {
    std::vector<std::shared_ptr<const map::Tile>> draw;  ///< non-overlapping, coarse where needed
    /// Tiles to load: those the drawn traversal met missing (visible first), then, at lower
    /// priority, the levels below them that this camera will draw (coarse first): loading all of
    /// `wanted` once makes the next selection complete for an unmoved camera.
    std::vector<map::TileRequest> wanted;
    std::vector<TileMorph> morph;  ///< parallel to draw (empty when options.morph is off)
    int finest_level = 0;
    std::size_t culled = 0;
};

/// `exists(id)`: the source has this tile. `resident(id)`: the loaded tile or null. `roots`: the
/// tiles the traversal starts from (TileSource::roots(): the root, or each mounted store's root).
LodSelection selectLod(const map::TileScheme& scheme, const Camera& camera, double aspect, int viewport_height,
                       const std::function<bool(map::TileId)>& exists,
                       const std::function<std::shared_ptr<const map::Tile>(map::TileId)>& resident,
                       const LodOptions& options = {}, const std::vector<map::TileId>& roots = {map::TileId{}});

/// Projected size in pixels of a geometric error of error_m seen at distance_m.
double screenSpaceError(double error_m, double distance_m, double fov_y_deg, int viewport_height);

/// Geometric error in metres of a tile of `level` (options.error_per_spacing x DEM spacing).
double levelError(const map::TileScheme& scheme, int level, const LodOptions& options);

/// Camera distance (metres, to the tile's box) below which a tile of `level` is refined into
/// its children: where screenSpaceError(levelError(level)) equals options.max_error_px.
double refineDistance(const map::TileScheme& scheme, int level, double fov_y_deg, int viewport_height,
                      const LodOptions& options);

/// Morph ranges of a tile of `level` through its kMorphLevels coarser levels (the rule above);
/// slot j (level - j -> level - j - 1) has end_m = 0 where level - j <= 0. Ancestors and
/// eye_dz_m are left for the caller.
TileMorph morphRange(const map::TileScheme& scheme, int level, double fov_y_deg, int viewport_height,
                     const LodOptions& options);

/// Vertical distance of a camera at eye_z from the band [min_height_m, max_height_m].
double morphEyeDz(double eye_z, const LodOptions& options);

/// f of the rule above for one morph slot: 0 = the finer level, 1 = the coarser one. end_m = 0: 0.
float morphFactor(float distance_m, float start_m, float end_m);

/// Distance used for the factors of a vertex at horizontal offset (dx, dy) from the camera.
float morphDistance(float dx, float dy, const TileMorph& morph);

/// S_L(d) of the rule above: `own` blended through `ancestors` (heights of levels L-1 .. L-4 at
/// the same place). Mirrored by shaders/terrain_tile.vert.
float morphedHeight(float distance_m, const TileMorph& morph, float own,
                    const std::array<float, kMorphLevels>& ancestors);

}  // namespace navmap::render
