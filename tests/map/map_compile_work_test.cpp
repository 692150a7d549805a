// SPDX-License-Identifier: Apache-2.0
// The bounded compile's work grows with its input, not faster: CompileStats::features_per_band
// (the features each band of tile columns tiles; one over several bands counts in each) summed
// over the bands, for one copy of the Andorra highways and two copies side by side, may grow at
// most 2.3 times. Counted, not timed.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <numeric>
#include <vector>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "synth_region.h"

using namespace navmap::map;
using navmap::map::test::repoData;
using navmap::map::test::ScratchDir;

TEST(CompileWork, FeaturesTiledPerBandGrowLinearlyWithCopiesOfTheInput) {
    ScratchDir dir("compile-work");
    std::size_t work[2] = {0, 0}, bands[2] = {0, 0}, roads[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
        const int copies = i + 1;
        tools::SynthRegionOptions r;
        r.osm = repoData("andorra-2021-04-14.osm.pbf");
        r.dem = repoData("N42E001.hgt");
        r.out_dir = dir / ("copies-" + std::to_string(copies));
        r.copies = copies;
        r.highways_only = true;
        std::filesystem::create_directories(r.out_dir);
        const tools::SynthRegion region = tools::synthesizeRegion(r);
        CompileOptions o;
        o.osm = region.osm;  // no DEM: flat terrain, the features are what counts here
        o.out = r.out_dir / "region.navmap";
        o.memory_limit_mib = 16;
        const CompileStats s = compileStore(o);
        bands[i] = s.features_per_band.size();
        work[i] = std::accumulate(s.features_per_band.begin(), s.features_per_band.end(), std::size_t{0});
        roads[i] = s.roads;
        std::printf("%d cop%s: %zu roads, %zu bands, %zu features tiled over the bands\n", copies,
                    copies == 1 ? "y" : "ies", roads[i], bands[i], work[i]);
        ASSERT_GE(bands[i], 2U) << "the limit splits the input into bands";
        EXPECT_GE(work[i], roads[i]) << "every road is tiled in a band";
    }
    EXPECT_GT(roads[1], roads[0] * 19 / 10) << "two copies hold twice the roads";
    EXPECT_LE(static_cast<double>(work[1]) / static_cast<double>(work[0]), 2.3);
}
