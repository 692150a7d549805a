// SPDX-License-Identifier: Apache-2.0
// The band stage of compileStore (compile_stages.h), bounded memory only: the spilled features
// measured, the tile columns cut into bands whose features fit the limit, the features
// distributed to per-band spill files, and the bands tiled one at a time.
#include <algorithm>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "compile_stages.h"
#include "navmap/map/tile_codec.h"

namespace navmap::map::detail {

namespace {

void clearFeatures(RawFeatures& f) {
    f.roads.clear();
    f.buildings.clear();
    f.areas.clear();
    f.points.clear();
    f.places.clear();
    f.graph_ways.clear();
    f.roads_counted.clear();
    f.buildings_counted.clear();
    f.areas_counted.clear();
    f.points_counted.clear();
    f.places_counted.clear();
}

/// The points of `one`'s feature in the store frame and at which levels it is shown (tileFeatures'
/// level-of-detail rules); no points when it shows nowhere.
std::vector<PlanarPoint> featureExtent(const RawFeatures& one, const Projection& proj, int leaf,
                                       std::function<bool(int level, double size)>& shown) {
    std::vector<PlanarPoint> pts;
    auto add = [&](const std::vector<GeoCoordinate>& ll) {
        for (const auto& p : ll) pts.push_back(proj.forward(p.lat_deg, p.lon_deg));
    };
    if (!one.roads.empty()) {
        const auto& r = one.roads.front();
        add(r.points);
        shown = [cls = r.cls](int, double size) { return size <= roadMaxTile(cls); };
    } else if (!one.buildings.empty()) {
        for (const auto& r : one.buildings.front().polygon.outers) add(r);
        shown = [leaf](int level, double) { return level == leaf - 1; };
    } else if (!one.areas.empty()) {
        const PPoly poly = projectPolygon(proj, one.areas.front().polygon);
        if (poly.outers.empty()) return {};
        pts = {{poly.bounds.min_x, poly.bounds.min_y}, {poly.bounds.max_x, poly.bounds.max_y}};
        shown = [area = poly.area](int, double size) { return area >= (size / 64.0) * (size / 64.0); };
    } else if (!one.places.empty()) {
        const auto& l = one.places.front();
        for (const auto& r : l.polygon.outers) add(r);
        shown = [max = placeMaxTile(static_cast<PlaceClass>(l.subclass))](int, double size) { return size <= max; };
    } else if (!one.points.empty()) {
        const auto& l = one.points.front();
        add({l.pos});
        shown = [max_tile = pointLabelMaxTile(l)](int, double size) { return size <= max_tile; };
    }
    return pts;
}

/// Reads features.spill, writes each feature's ranges of fine bands to feature-bands.spill and
/// returns the bands within `budget`.
std::vector<BandRange> measureBands(const SpillDir& spill, const Frame& frame, std::uint64_t budget) {
    std::vector<std::uint64_t> from(kMaxBands, 0), to(kMaxBands, 0);  // bytes by first / last fine band
    SpillReader in(spill / "features.spill");
    SpillWriter ranges_out(spill / "feature-bands.spill", std::size_t{1} << 20);
    std::vector<std::uint8_t> record, ranges;
    RawFeatures one;
    while (in.next(record)) {
        clearFeatures(one);
        decodeRecord(in, record, one);
        ranges.clear();
        // A feature in two ranges of one band counts twice there: on the safe side.
        for (const auto& [lo, hi] : featureBands(one, frame.proj, frame.scheme, frame.grid, kMaxBands)) {
            from[static_cast<std::size_t>(lo)] += record.size();
            to[static_cast<std::size_t>(hi)] += record.size();
            ranges.push_back(static_cast<std::uint8_t>(lo));
            ranges.push_back(static_cast<std::uint8_t>(hi));
        }
        ranges_out.append(ranges);
    }
    ranges_out.close();
    return bandsWithin(from, to, budget);
}

std::filesystem::path bandPath(const SpillDir& spill, int k) {
    return spill / ("band-" + std::to_string(k) + ".spill");
}

std::filesystem::path tilesPath(const SpillDir& spill, int k) {
    return spill / ("tiles-" + std::to_string(k) + ".spill");
}

}  // namespace

void decodeRecord(const SpillReader& reader, std::span<const std::uint8_t> record, RawFeatures& out) {
    std::string error;
    if (!decodeFeature(record, out, error)) {
        throw SpillError(reader.path().string() + ": damaged feature record: " + error);
    }
}

std::size_t featureCount(const RawFeatures& f) {
    return f.roads.size() + f.buildings.size() + f.areas.size() + f.points.size() + f.places.size();
}

/// Runs of the fine bands 0..N-1 (N = from.size()) whose features take at most `budget` spilled
/// bytes, from west to east, each as long as it fits (a fine band over the budget on its own
/// is a band of its own). from[k] / to[k]: bytes of the features whose ranges of fine bands
/// start / end at k (featureBands(); a feature with two ranges counts in each). The ranges
/// touching fine bands a..b are those starting at or before b less those ending before a.
std::vector<BandRange> bandsWithin(const std::vector<std::uint64_t>& from, const std::vector<std::uint64_t>& to,
                                   std::uint64_t budget) {
    const int n = static_cast<int>(from.size());
    std::vector<std::uint64_t> starting(from.size() + 1, 0), ended(from.size() + 1, 0);  // prefix sums
    for (std::size_t k = 0; k < from.size(); ++k) {
        starting[k + 1] = starting[k] + from[k];
        ended[k + 1] = ended[k] + to[k];
    }
    std::vector<BandRange> bands;
    for (int a = 0; a < n;) {
        int b = a;
        while (b + 1 < n && starting[static_cast<std::size_t>(b) + 2] - ended[static_cast<std::size_t>(a)] <= budget)
            ++b;
        bands.push_back({a, b, n});
        a = b + 1;
    }
    return bands;
}

/// The bands of tile columns that build a tile holding the feature `one` holds: at each level
/// where it appears (tileFeatures' level-of-detail rules), the bands of the columns its bounds
/// overlap (its label anchors lie inside them). Bounds grow by a metre for rounding. As ranges
/// of bands, one per level, sorted and merged where they overlap or touch: a feature in the
/// west shown on a coarse tile of the middle goes to the bands of the coarse tiles that hold it,
/// not to every band in between.
std::vector<std::pair<int, int>> featureBands(const RawFeatures& one, const Projection& proj, const TileScheme& scheme,
                                              const ShardGrid& grid, int bands) {
    const int leaf = scheme.leafLevel();
    std::function<bool(int level, double size)> shown;
    const std::vector<PlanarPoint> pts = featureExtent(one, proj, leaf, shown);
    if (pts.empty()) return {};
    Box box = boundsOf(pts);
    box.min_x -= 1.0;
    box.min_y -= 1.0;
    box.max_x += 1.0;
    box.max_y += 1.0;
    std::vector<std::pair<int, int>> ranges;
    for (int level = 0; level <= leaf; ++level) {
        if (level != leaf && !shown(level, scheme.tileSize(level))) continue;
        const TileRange r = scheme.range(level, box);
        if (r.empty) continue;
        const auto l = static_cast<std::uint8_t>(level);
        ranges.emplace_back(tileShard({l, r.x0, 0}, bands, grid), tileShard({l, r.x1, 0}, bands, grid));
    }
    std::sort(ranges.begin(), ranges.end());
    std::vector<std::pair<int, int>> merged;
    for (const auto& r : ranges) {
        if (!merged.empty() && r.first <= merged.back().second + 1) {
            merged.back().second = std::max(merged.back().second, r.second);
        } else {
            merged.push_back(r);
        }
    }
    return merged;
}

BandPlan planBands(const SpillDir& spill, const Frame& frame, ShardSpec shard, std::uint64_t limit_bytes) {
    // Bands are runs of kMaxBands equal column bands ("fine bands") whose features fit a
    // band's budget, half the limit (a third is the DEM's): measured first, from each
    // feature's ranges of fine bands. The ranges are kept, a record per feature in
    // feature-bands.spill, so that distributing the features needs no second decoding.
    static_assert(kMaxBands <= 256, "a fine band is one byte in feature-bands.spill");
    BandPlan plan;
    plan.budget = static_cast<std::uint64_t>(static_cast<double>(limit_bytes) / 2.0 / kMemoryPerSpilledByte);
    plan.bands = measureBands(spill, frame, plan.budget);
    const int n_bands = static_cast<int>(plan.bands.size());
    // Bands that hold none of this job's columns get no features.
    plan.used.assign(static_cast<std::size_t>(n_bands), 0);
    plan.band_of.assign(kMaxBands, 0);
    for (int k = 0; k < n_bands; ++k) {
        const BandRange& b = plan.bands[static_cast<std::size_t>(k)];
        for (int f = b.first; f <= b.last; ++f) plan.band_of[static_cast<std::size_t>(f)] = k;
        for (int level = 0; level <= frame.scheme.leafLevel(); ++level) {
            const auto job = shardColumns(level, shard, frame.grid);
            const auto cols = bandColumns(level, b.first, b.last, b.count, frame.grid);
            if (std::max(job.first, cols.first) <= std::min(job.second, cols.second)) plan.used[k] = 1;
        }
    }
    return plan;
}

void splitIntoBands(const SpillDir& spill, const BandPlan& plan) {
    {
        const std::size_t n_bands = plan.bands.size();
        std::vector<std::unique_ptr<SpillWriter>> band_out(n_bands);
        for (std::size_t k = 0; k < n_bands; ++k) {
            if (plan.used[k]) band_out[k] = std::make_unique<SpillWriter>(bandPath(spill, static_cast<int>(k)));
        }
        SpillReader in(spill / "features.spill");
        SpillReader ranges_in(spill / "feature-bands.spill");
        std::vector<std::uint8_t> record, ranges;
        std::vector<int> targets;  // the bands of one feature
        while (in.next(record)) {
            if (!ranges_in.next(ranges) || ranges.size() % 2 != 0) {
                throw SpillError(ranges_in.path().string() +
                                 ": damaged: not one record of band ranges per feature of " + in.path().string());
            }
            targets.clear();
            for (std::size_t i = 0; i < ranges.size(); i += 2) {
                for (int k = plan.band_of[ranges[i]]; k <= plan.band_of[ranges[i + 1]]; ++k) targets.push_back(k);
            }
            std::sort(targets.begin(), targets.end());
            targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
            bool first = true;
            for (const int k : targets) {
                if (!band_out[k]) continue;
                // Counted in its first band only.
                record[0] = static_cast<std::uint8_t>(first ? (record[0] & ~kRepeatFlag) : (record[0] | kRepeatFlag));
                band_out[k]->append(record);
                first = false;
            }
        }
        for (auto& b : band_out) {
            if (b) b->close();
        }
    }
    std::filesystem::remove(spill / "features.spill");
    std::filesystem::remove(spill / "feature-bands.spill");
}

RawFeatures readBand(const SpillDir& spill, int k, std::uint64_t& bytes) {
    RawFeatures band;
    {
        SpillReader in(bandPath(spill, k));
        bytes = in.size();
        std::vector<std::uint8_t> record;
        while (in.next(record)) decodeRecord(in, record, band);
    }
    std::filesystem::remove(bandPath(spill, k));
    return band;
}

BandTiles tileBands(const SpillDir& spill, const BandPlan& plan, TilingContext& ctx, CompileStats& stats,
                    CompileLog& log) {
    // Each band's tiles, encoded, in a file of its own; where each tile is.
    const int n_bands = static_cast<int>(plan.bands.size());
    BandTiles out;
    out.files.resize(static_cast<std::size_t>(n_bands));
    for (int k = 0; k < n_bands; ++k) {
        if (!plan.used[k]) continue;
        std::uint64_t band_bytes = 0;
        RawFeatures band = readBand(spill, k, band_bytes);
        SpillWriter tiles_out(tilesPath(spill, k), std::size_t{1} << 20);
        ctx.band = plan.bands[static_cast<std::size_t>(k)];
        std::vector<std::uint8_t> payload;
        std::size_t band_tiles = 0;
        ctx.emit = [&](const Tile& t) {
            payload.clear();
            for (int i = 0; i < 8; ++i) payload.push_back(static_cast<std::uint8_t>(t.id.key() >> (8 * i)));
            const auto encoded = encodeTile(t);
            payload.insert(payload.end(), encoded.begin(), encoded.end());
            out.refs.push_back({t.id.key(), k, tiles_out.append(payload)});
            ++band_tiles;
        };
        stats.features_per_band.push_back(featureCount(band));
        tileFeatures(band, ctx, stats);
        tiles_out.close();
        out.files[static_cast<std::size_t>(k)] = std::make_unique<SpillReader>(tilesPath(spill, k));
        log.log("band " + std::to_string(k + 1) + "/" + std::to_string(n_bands) + ": " +
                std::to_string(featureCount(band)) + " features (" + mib(band_bytes) + "), " +
                std::to_string(band_tiles) + " tiles");
        band = RawFeatures{};
#ifdef __GLIBC__
        // The band's many small blocks are free now: hand them back, so that the next band
        // does not stack its memory on what the allocator keeps.
        ::malloc_trim(0);
#endif
    }
    // The single compile's order: level by level, by key within a level (TileId::key() sorts so).
    std::sort(out.refs.begin(), out.refs.end(),
              [](const BandTiles::Ref& a, const BandTiles::Ref& b) { return a.key < b.key; });
    return out;
}

}  // namespace navmap::map::detail
