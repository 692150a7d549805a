// SPDX-License-Identifier: Apache-2.0
#pragma once
// A conservative horizon of the drawn terrain as seen from the eye, to leave out the road blocks
// the terrain hides before their vertices cost anything (MapLayers::cull_hidden_roads). In snail's
// views most distant roads lie behind ridges. Occlusion queries on the GPU would find them
// exactly, but on llvmpipe waiting for them costs as much as drawing the roads
// (docs/rendering.md); this is worked out on the CPU beside the render thread.
//
// Conservative: a block is called hidden only if every line of sight from the eye to its box
// passes below the lowest the drawn terrain can lie somewhere nearer than the box. The eye is
// above the drawn surface, so such a line meets the surface first, and the terrain's depth there
// wins over the road's.

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace navmap::render {

/// The lowest the drawn surface of one tile can lie in each cell of its grid: the least of the
/// cell's four vertices over the tile's own heights and those of every geomorph target
/// (terrain_tile.vert blends between them, and the surface over a cell is two triangles between
/// its vertices).
struct TerrainFloor {
    glm::dvec2 origin{0.0};  ///< store-frame metres of the south-west corner
    double cell_m = 0.0;
    int cells = 0;           ///< per side
    std::vector<float> low;  ///< cells^2, row 0 south
};

/// `heights`: grid_size^2 (row 0 south), the tile's own; `ancestor_heights`: the geomorph
/// targets at the same vertices (empty vectors are skipped).
TerrainFloor terrainFloor(glm::dvec2 origin, double size_m, int grid_size, std::span<const float> heights,
                          std::span<const std::vector<float>> ancestor_heights);

class TerrainHorizon {
public:
    /// From `eye` over the azimuths [az_from, az_to] (radians, counter-clockwise from east,
    /// az_from < az_to <= az_from + 2 pi) in `bins` bins, along lines of sight out to `last_m`
    /// (horizontal metres), over the drawn tiles' `floors`. `ground_m`: the highest the drawn
    /// surface lies under the eye; the horizon hides nothing unless the eye is above it.
    void build(glm::dvec3 eye, double ground_m, std::span<const TerrainFloor* const> floors, double az_from,
               double az_to, int bins, double last_m);
    /// Whether the drawn terrain hides all of the box lo..hi (store frame) from the eye, for
    /// points drawn at `keep` of their distance (the roads' view-space scale, seed 3.6.2).
    [[nodiscard]] bool hides(glm::dvec3 lo, glm::dvec3 hi, double keep) const;
    [[nodiscard]] bool empty() const { return m_bins == 0; }

    /// The first line-of-sight step, metres: nearer terrain is not looked at (the near plane
    /// may clip it).
    static constexpr double kFirstM = 40.0;
    /// Each step this much farther than the one before.
    static constexpr double kStepRatio = 1.1;

private:
    glm::dvec3 m_eye{0.0};
    double m_az_from = 0.0, m_bin_rad = 0.0;
    int m_bins = 0;
    std::vector<double> m_radius;  ///< per step, horizontal metres
    /// Per bin, per step: the greatest slope (height over horizontal distance, from the eye) up
    /// to which the terrain at that step or nearer hides every line of sight in the bin.
    std::vector<float> m_slope;
};

}  // namespace navmap::render
