// SPDX-License-Identifier: Apache-2.0
// Procedural vegetation (seed 6.7.1): plants compete, seed only in forest and scrub, keep off roads
// and buildings, and never grow above their species' timber line.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/ortho/tile_sampler.h"
#include "ortho/vegetation.h"
#include "ortho_test_tile.h"

namespace {

using navmap::map::ortho::SuperLandCover;
using namespace navmap::render::ortho;

TEST(Vegetation, GrowthFallsToZeroOverTheTransitionZone) {
    const Species s = defaultSpecies()[0];
    ASSERT_EQ(s.timber_line_m, 1800.0f);
    EXPECT_EQ(growthFactor(s, 500.0f), 1.0f);
    EXPECT_EQ(growthFactor(s, s.timber_line_m - s.transition_m), 1.0f);
    EXPECT_NEAR(growthFactor(s, s.timber_line_m - 0.5f * s.transition_m), 0.5f, 1e-6f);
    EXPECT_EQ(growthFactor(s, s.timber_line_m), 0.0f);
    EXPECT_EQ(growthFactor(s, 2500.0f), 0.0f);
}

TEST(Vegetation, NoPlantAboveTheTimberLineAndPlantsBelowIt) {
    // Forest everywhere on a slope from 500 m (south) to 3000 m (north).
    const auto tile = navmap::test::orthoTile([](double, double) { return SuperLandCover::Forest; },
                                              [](double, double y) { return static_cast<float>(500.0 + 1.25 * y); });
    const VegetationResult v = simulateVegetation(*tile);
    ASSERT_GT(v.plants.size(), 1000u);
    EXPECT_GT(v.died_competing, 0u);
    const navmap::map::ortho::OrthoTileSampler s(*tile);
    const auto species = defaultSpecies();
    std::array<int, 3> count{};
    std::array<float, 3> highest{};
    for (const Plant& p : v.plants) {
        const float h = s.pixel(p.position.x, p.position.y).elevation_m;
        const Species& sp = species[p.species];
        ASSERT_LT(h, sp.timber_line_m) << sp.name << " at " << h << " m";
        EXPECT_LE(p.radius_m, sp.max_radius_m);
        ++count[p.species];
        highest[p.species] = std::max(highest[p.species], h);
    }
    // Each species grows, and up into its transition zone: broadleaf to 1800 m, conifers between
    // 1800 and 2300 m, above that only shrubs.
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_GT(count[k], 20) << species[k].name;
        EXPECT_GT(highest[k], species[k].timber_line_m - species[k].transition_m) << species[k].name;
    }
    // Nothing at all above the highest line (2700 m: y > 1760 m, give or take the layer's whole
    // metres), plenty below the lowest one.
    EXPECT_TRUE(std::none_of(v.plants.begin(), v.plants.end(), [](const Plant& p) { return p.position.y > 1762.0f; }));
    EXPECT_GT(std::count_if(v.plants.begin(), v.plants.end(), [](const Plant& p) { return p.position.y < 800.0f; }),
              500);
    // Deterministic per tile.
    const VegetationResult again = simulateVegetation(*tile);
    ASSERT_EQ(again.plants.size(), v.plants.size());
    EXPECT_EQ(again.plants[100].position, v.plants[100].position);
}

TEST(Vegetation, SeedsOnlyInForestAndScrubAndOffRoadsAndBuildings) {
    auto tile = navmap::test::orthoTile(
        [](double x, double) { return x < 1000 ? SuperLandCover::Forest : SuperLandCover::Grass; },
        [](double, double) { return 600.0f; });
    navmap::map::Road road;
    road.cls = navmap::map::RoadClass::Secondary;  // 8 m kept free on either side
    road.points = {{500, 0}, {500, 2000}};
    tile->roads.push_back(road);
    navmap::map::Building house;  // a 60 m square at (200..260, 1000..1060)
    house.footprint.vertices = {{200, 1000}, {260, 1000}, {260, 1060}, {200, 1060}};
    house.footprint.ring_ends = {4};
    house.footprint.indices = {0, 1, 2, 0, 2, 3};
    house.height_m = 10;
    tile->buildings.push_back(house);
    const VegetationResult v = simulateVegetation(*tile);
    ASSERT_GT(v.plants.size(), 500u);
    const float texel = 2000.0f / 256;
    for (const Plant& p : v.plants) {
        EXPECT_LT(p.position.x, 1000.0f);
        EXPECT_GT(std::abs(p.position.x - 500.0f), 8.0f - texel);
        const bool in_house = p.position.x > 200 + texel && p.position.x < 260 - texel && p.position.y > 1000 + texel &&
                              p.position.y < 1060 - texel;
        EXPECT_FALSE(in_house) << p.position.x << ", " << p.position.y;
    }
    // Plants do not overlap after the last competition step.
    for (std::size_t i = 0; i < v.plants.size(); i += 7) {
        for (std::size_t j = i + 1; j < v.plants.size(); ++j) {
            const float d = glm::length(v.plants[i].position - v.plants[j].position);
            ASSERT_GE(d, v.plants[i].radius_m + v.plants[j].radius_m - 1e-3f);
        }
    }
    // Pair-wise brightness changes cancel by crown area (seed 6.7.5).
    double sum = 0, total = 0;
    for (std::size_t i = 0; i < v.plants.size(); ++i) {
        const double w = v.plants[i].radius_m * v.plants[i].radius_m;
        sum += v.plants[i].variation * w;
        total += std::abs(v.plants[i].variation) * w;
    }
    if (v.plants.size() % 2 == 1) {
        EXPECT_EQ(v.plants.back().variation, 0.0f) << "the odd plant out has no partner";
    }
    EXPECT_NEAR(sum, 0.0, 1e-3 * total);
    // Grass only: nothing seeds.
    const auto grass = navmap::test::orthoTile([](double, double) { return SuperLandCover::Grass; },
                                               [](double, double) { return 600.0f; });
    EXPECT_TRUE(simulateVegetation(*grass).plants.empty());
}

}  // namespace
