// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: tile payload and road graph decoding on arbitrary bytes (the tile store
// is input; a corrupt or hostile file must never crash the daemon). Also linked into
// map_store_test, which runs it over a corpus of bad inputs in the normal suite.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "navmap/map/road_graph.h"
#include "navmap/map/tile.h"
#include "navmap/map/tile_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    navmap::map::Tile tile;
    std::string error;
    if (navmap::map::decodeTile(bytes, tile, error)) {
        // A decoded tile must be internally consistent: every index in range.
        for (const auto& b : tile.buildings) {
            for (auto i : b.footprint.indices) {
                if (i >= b.footprint.vertices.size()) __builtin_trap();
            }
        }
        (void)tile.byteSize();
    }
    navmap::map::RoadGraph graph;
    if (navmap::map::decodeRoadGraph(bytes, graph, error)) {
        for (std::uint32_t n = 0; n < graph.nodes.size(); ++n) (void)graph.outEdges(n);
    }
    return 0;
}
