// SPDX-License-Identifier: Apache-2.0
#pragma once
// Procedural vegetation over a tile's forest and scrub (seed 6.7.1): a simplified version of Deussen
// et al.'s plant competition. Plants are circles; each step they grow, seed new plants nearby and,
// where circles overlap, the weaker one dies. Competitive ability comes from the water available,
// the species' preference for wet or dry ground and its relative size. Each species has a timber
// line above which it never grows and a transition zone below it in which its growth rate falls
// linearly to zero. Neighbours are found on a uniform grid. GL-free; private to render/. The
// orthoimage generator draws the plants of the images that ask for them (leaf tiles: close range).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "navmap/map/tile.h"

namespace navmap::render::ortho {

struct Species {
    std::string name;
    float max_radius_m = 5.0f;
    float growth_m = 0.5f;  ///< radius added per step at full rate
    int seeds = 2;          ///< new plants per step of a plant past half its size
    float seed_distance_m = 10.0f;
    float wet_preference = 0.5f;  ///< 0 dry .. 1 wet
    float timber_line_m = 1800.0f;
    float transition_m = 600.0f;  ///< the growth rate falls linearly to 0 over this band below the line
};

/// Broadleaf trees (the seed's tree limit: 1800 m, transition 600 m of the seed's 500-700 m),
/// conifers (up to 2300 m, as mountain pines in the Pyrenees) and shrubs (up to 2700 m).
std::vector<Species> defaultSpecies();

struct Plant {
    glm::vec2 position{0.0f};  ///< tile-local metres
    float radius_m = 0.0f;
    std::uint8_t species = 0;
    /// Brightness change against the network's colour; pairs of plants cancel by crown area.
    float variation = 0.0f;
};

struct VegetationOptions {
    int steps = 20;                   ///< seed: "only done for a few steps (i.e., 20)"
    float initial_spacing_m = 14.0f;  ///< one initial plant per this square of seeding area
    std::size_t max_plants = 60000;
    std::vector<Species> species = defaultSpecies();
};

struct VegetationResult {
    std::vector<Plant> plants;
    std::size_t seeded = 0, died_competing = 0, died_old = 0;
};

/// Growth rate factor of a species at an elevation: 1 below the transition zone, falling linearly
/// to 0 at the timber line, 0 above it.
float growthFactor(const Species& species, float elevation_m);

/// Runs the simulation over the tile's forest and scrub texels (its super land cover), seeding only
/// there and not on roads, buildings or water; deterministic per tile id. Empty without layers.
VegetationResult simulateVegetation(const map::Tile& tile, const VegetationOptions& options = {});

}  // namespace navmap::render::ortho
