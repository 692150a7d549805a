// SPDX-License-Identifier: Apache-2.0
#pragma once
// Procedural fields over a tile's farmland (seed 6.7.2): a low-resolution grid aligned to the major
// roads by an angle histogram, adapted towards the silhouette of the farmland in the tile's super
// land cover, its cells with farmland subdivided into parcels down to an area threshold, and crop
// patterns picked from an atlas by a random walk. GL-free; private to render/. The orthoimage
// generator (gl/ortho_generator.cpp) draws the parcels through a mask of the farmland texels, so
// nothing is drawn outside the farmland, while the parcels cover every farmland texel whole.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/map/tile.h"

namespace navmap::render::ortho {

inline constexpr int kCropPatterns = 8;  ///< entries of the crop atlas (ortho_fields.frag)

struct FieldParcel {
    std::array<glm::vec2, 4> corners;  ///< tile-local metres, counter-clockwise around the parcel
    int pattern = 0;                   ///< crop pattern (atlas entry), 0..kCropPatterns-1
    /// Brightness and hue change of the parcel against the network's colour: parcels come in pairs
    /// whose changes, weighted by their farmland, cancel, so the farmland's mean colour stays the
    /// network's (seed 6.7.5).
    float variation = 0.0f;
    float hue = 0.0f;
    float angle = 0.0f;   ///< radians, direction of the crop rows
    int farm_texels = 0;  ///< farmland texel centres inside the parcel
};

struct FieldOptions {
    float cell_m = 240.0f;                 ///< base grid cell (before adaptation)
    int adapt_iterations = 10;             ///< towards the silhouette (seed: 10)
    float max_shift = 0.3f;                ///< how far a vertex may move, in cells (keeps the cells convex)
    float min_parcel_m2 = 8000.0f;         ///< subdivision stops between these areas (random per cell)
    float max_parcel_m2 = 30000.0f;        ///< (seed: 0.01-2 km^2; smaller here for 2 km tiles)
    float snap_m = 12.0f;                  ///< grid vertices this close to a major road move onto it
    int atlas_window = kCropPatterns / 2;  ///< m of the random walk's sliding window [o, o + m)
    int walk_range = 6;                    ///< |S_k| bound of the random walk
};

struct FieldGrid {
    float angle = 0.0f;  ///< grid orientation from the angle histogram (radians, in [0, pi/2))
    std::vector<FieldParcel> parcels;
};

/// The farmland texels of the tile's super land cover (tile.ortho.cover), row 0 south: 1 or 0.
std::vector<std::uint8_t> farmlandMask(const map::Tile& tile);

/// Dominant direction of the major roads (mod 90 degrees), from a length-weighted histogram of
/// 1-degree bins smoothed over 5; 0 without roads.
float roadGridAngle(const map::Tile& tile);

/// Parcels whose union covers every farmland texel of the tile whole (not only its centre) and
/// each of which holds farmland; deterministic per tile id. Empty without farmland or layers.
FieldGrid buildFieldGrid(const map::Tile& tile, const FieldOptions& options = {});

/// Whether the point lies in the parcel (two triangles, edges included).
bool parcelContains(const FieldParcel& parcel, glm::vec2 point);

}  // namespace navmap::render::ortho
