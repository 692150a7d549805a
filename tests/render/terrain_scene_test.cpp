// SPDX-License-Identifier: Apache-2.0
// Unit tests of the CPU side of the first scene: the real SRTM tile, void filling and the mesh.
#include <gtest/gtest.h>

#include <cmath>

#include "navmap/map/dem.h"
#include "terrain_scene.h"
#include "test_paths.h"

namespace {

using navmap::test::dataDir;

TEST(TerrainScene, VoidsOfTheRealTileAreFilledWithinTheirSurroundings) {
    const navmap::map::Dem tile = navmap::map::loadHgt(dataDir() / "N42E001.hgt");
    ASSERT_EQ(tile.void_count, 7652u);  // the tile's documented void count
    navmap::map::Dem dem = navmap::map::crop(tile, 42.40, 1.38, 42.68, 1.82);
    ASSERT_GT(dem.void_count, 300u);
    const navmap::map::Dem original = dem;
    EXPECT_EQ(navmap::map::fillVoids(dem), original.void_count);

    std::size_t checked = 0;
    for (int r = 0; r < dem.rows; ++r) {
        for (int c = 0; c < dem.cols; ++c) {
            const float h = dem.at(r, c);
            ASSERT_FALSE(std::isnan(h));
            if (!std::isnan(original.at(r, c))) {
                ASSERT_EQ(h, original.at(r, c)) << "valid samples must stay untouched";
                continue;
            }
            // A filled sample lies within the range of the valid samples around it: no pits, no spikes.
            float lo = 1e9f, hi = -1e9f;
            for (int dr = -32; dr <= 32; ++dr) {
                for (int dc = -32; dc <= 32; ++dc) {
                    const int rr = r + dr, cc = c + dc;
                    if (rr < 0 || cc < 0 || rr >= dem.rows || cc >= dem.cols) continue;
                    const float v = original.at(rr, cc);
                    if (std::isnan(v)) continue;
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            }
            ASSERT_LE(lo, hi) << "no valid sample near void at " << r << "," << c;
            EXPECT_GE(h, lo - 0.5f);
            EXPECT_LE(h, hi + 0.5f);
            ++checked;
        }
    }
    EXPECT_EQ(checked, original.void_count);
}

TEST(TerrainScene, HgtOfWrongSizeIsRejectedNamingTheFile) {
    const auto path = std::filesystem::temp_directory_path() / "N10E010.hgt";
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_NE(f, nullptr);
        const char junk[100] = {};
        std::fwrite(junk, 1, sizeof junk, f);
        std::fclose(f);
    }
    try {
        (void)navmap::map::loadHgt(path);
        FAIL() << "a 100-byte .hgt must be rejected";
    } catch (const navmap::map::DemError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("100 bytes"), std::string::npos) << e.what();
    }
    std::filesystem::remove(path);
}

TEST(TerrainScene, MeshCoversAndorraWithUpwardNormals) {
    const auto scene = navmap::render::loadTerrainScene(dataDir() / "N42E001.hgt");
    const auto& mesh = scene.mesh;
    ASSERT_GT(mesh.vertices.size(), 100000u);
    EXPECT_EQ(mesh.indices.size() % 3, 0u);
    // Heights of the crop: Gran Valira at ~800 m up to Coma Pedrosa (2899 m in SRTM).
    EXPECT_GT(mesh.min_height, 300.0f);
    EXPECT_LT(mesh.min_height, 900.0f);
    EXPECT_GT(mesh.max_height, 2850.0f);
    EXPECT_LT(mesh.max_height, 3150.0f);
    for (const auto& v : mesh.vertices) {
        ASSERT_GT(v.normal.z, 0.0f);
        ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
    }
    // The box is about 36 km x 31 km.
    const auto& first = mesh.vertices.front().position;
    const auto& last = mesh.vertices.back().position;
    EXPECT_NEAR(last.x - first.x, 36000.0f, 1500.0f);
    EXPECT_NEAR(first.y - last.y, 31000.0f, 1500.0f);
    // Andorra la Vella (42.5063 N, 1.5218 E) lies at about 1020-1080 m in SRTM.
    navmap::map::Dem tile = navmap::map::loadHgt(dataDir() / "N42E001.hgt");
    EXPECT_NEAR(tile.sample(42.5063, 1.5218), 1050.0f, 60.0f);
}

TEST(TerrainScene, TrianglesFaceUp) {
    const auto scene = navmap::render::loadTerrainScene(dataDir() / "N42E001.hgt");
    const auto& m = scene.mesh;
    for (std::size_t i = 0; i < m.indices.size(); i += 3 * 997) {
        const glm::vec3 a = m.vertices[m.indices[i]].position;
        const glm::vec3 b = m.vertices[m.indices[i + 1]].position;
        const glm::vec3 c = m.vertices[m.indices[i + 2]].position;
        EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f) << "triangle " << i / 3 << " is clockwise from above";
    }
}

}  // namespace
