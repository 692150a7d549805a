// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/shard.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "navmap/common/untrusted_file.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/compile/store_writer.h"
#include "navmap/map/tile_store.h"

namespace navmap::map {

namespace {

constexpr const char* kManifestFormat = "navmap-shard-1";

std::string describe(ShardSpec s) { return std::to_string(s.index) + "/" + std::to_string(s.count); }

}  // namespace

Box dataBox(const Projection& frame, double south, double west, double north, double east) {
    const PlanarPoint corners[4] = {frame.forward(south, west), frame.forward(south, east), frame.forward(north, west),
                                    frame.forward(north, east)};
    return boundsOf(corners);
}

ShardGrid shardGridOf(const TileScheme& scheme, const Box& data_box) {
    const TileRange r = scheme.range(scheme.leafLevel(), data_box);
    if (r.empty) return {scheme.leafLevel(), 0, (std::uint32_t{1} << scheme.leafLevel()) - 1};
    return {scheme.leafLevel(), r.x0, r.x1};
}

ShardGrid shardGridOf(const StoreInfo& info) {
    return shardGridOf(info.scheme, dataBox(Projection(info.origin_lat, info.origin_lon), info.south, info.west,
                                            info.north, info.east));
}

int tileShard(TileId id, int shard_count, const ShardGrid& grid) {
    if (shard_count <= 1) return 0;
    // The column's centre in doubled leaf columns, against the grid's doubled range: exact in
    // integers, so every job and the merge agree on every tile.
    const int up = std::max(0, grid.leaf_level - static_cast<int>(id.level));
    const std::int64_t centre = (2 * std::int64_t{id.x} + 1) << up;
    const std::int64_t from = 2 * std::int64_t{grid.first};
    const std::int64_t width = 2 * (std::int64_t{grid.last} + 1 - std::int64_t{grid.first});
    if (centre <= from) return 0;
    const std::int64_t band = (centre - from) * shard_count / width;
    return static_cast<int>(std::min<std::int64_t>(band, shard_count - 1));
}

std::pair<std::uint32_t, std::uint32_t> shardColumns(int level, ShardSpec spec, const ShardGrid& grid) {
    return bandColumns(level, spec.index, spec.index, spec.count, grid);
}

std::pair<std::uint32_t, std::uint32_t> bandColumns(int level, int first_band, int last_band, int count,
                                                    const ShardGrid& grid) {
    const std::uint64_t columns = std::uint64_t{1} << level;
    if (count <= 1) return {0, static_cast<std::uint32_t>(columns - 1)};
    // Bands grow west to east: the first column of band >= k, by bisection.
    auto first = [&](int k) {
        std::uint64_t lo = 0, hi = columns;
        while (lo < hi) {
            const std::uint64_t mid = (lo + hi) / 2;
            if (tileShard({static_cast<std::uint8_t>(level), static_cast<std::uint32_t>(mid), 0}, count, grid) >= k)
                hi = mid;
            else
                lo = mid + 1;
        }
        return lo;
    };
    const std::uint64_t lo = first(first_band);
    const std::uint64_t hi = first(last_band + 1);
    if (lo >= hi) return {1, 0};
    return {static_cast<std::uint32_t>(lo), static_cast<std::uint32_t>(hi - 1)};
}

ShardSpec parseShardSpec(const std::string& text) {
    const auto bad = [&] {
        return CompileError("--shard: '" + text + "' is not K/N with 1 <= N <= " + std::to_string(kMaxShards) +
                            " and 0 <= K < N");
    };
    const auto slash = text.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) throw bad();
    auto number = [&](const std::string& s) {
        if (s.size() > 5 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) throw bad();
        return std::stoi(s);
    };
    ShardSpec spec;
    spec.index = number(text.substr(0, slash));
    spec.count = number(text.substr(slash + 1));
    if (spec.count < 1 || spec.count > kMaxShards || spec.index >= spec.count) throw bad();
    return spec;
}

std::filesystem::path shardManifestPath(const std::filesystem::path& store) {
    return std::filesystem::path(store.string() + ".shard.json");
}

void writeShardManifest(const std::filesystem::path& path, const ShardManifest& m) {
    nlohmann::ordered_json j;
    j["format"] = kManifestFormat;
    j["shard"] = m.shard.index;
    j["shards"] = m.shard.count;
    j["tiles"] = m.tiles;
    j["graph"] = m.graph;
    j["fingerprint"] = m.fingerprint;
    const std::string text = j.dump(2) + "\n";
    const std::filesystem::path tmp(path.string() + ".tmp");
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) throw CompileError(tmp.string() + ": cannot write: " + std::strerror(errno));
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw CompileError(path.string() + ": cannot write: " + ec.message());
    }
}

ShardManifest readShardManifest(const std::filesystem::path& path) {
    // A regular file of at most 1 MiB (a manifest is a few hundred bytes), opened without blocking.
    std::string problem;
    const auto text = UntrustedFile::readText(path, FileKind{"shard manifest", std::uint64_t{1} << 20}, problem);
    if (!text) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw CompileError(path.string() + ": no such file (each shard store has its manifest beside it)");
        throw CompileError(problem);
    }
    const auto j = nlohmann::json::parse(*text, nullptr, false);
    const auto bad = [&](const std::string& why) {
        return CompileError(path.string() + ": not a shard manifest: " + why);
    };
    if (j.is_discarded() || !j.is_object()) throw bad("not a JSON object");
    if (j.value("format", std::string{}) != kManifestFormat)
        throw bad("format is not \"" + std::string(kManifestFormat) + "\"");
    for (const char* key : {"shard", "shards", "tiles"}) {
        if (!j.contains(key) || !j[key].is_number_unsigned()) throw bad(std::string("\"") + key + "\" is not a count");
    }
    if (!j.contains("graph") || !j["graph"].is_boolean()) throw bad("\"graph\" is not true or false");
    if (!j.contains("fingerprint") || !j["fingerprint"].is_string()) throw bad("\"fingerprint\" is not a string");
    ShardManifest m;
    const auto shard = j["shard"].get<std::uint64_t>(), shards = j["shards"].get<std::uint64_t>();
    if (shards < 1 || shards > kMaxShards || shard >= shards) {
        throw bad("shard " + std::to_string(shard) + " of " + std::to_string(shards) + " is not a shard");
    }
    m.shard = {static_cast<int>(shard), static_cast<int>(shards)};
    m.tiles = j["tiles"].get<std::uint64_t>();
    m.graph = j["graph"].get<bool>();
    m.fingerprint = j["fingerprint"].get<std::string>();
    return m;
}

MergeStats mergeShards(const std::vector<std::filesystem::path>& stores, const std::filesystem::path& out,
                       const std::function<void(const std::string&)>& log) {
    const auto t0 = std::chrono::steady_clock::now();
    if (stores.empty()) throw CompileError("merge: no shard stores given");
    struct Shard {
        std::filesystem::path path;
        ShardManifest manifest;
        std::shared_ptr<TileStore> store;
    };
    std::vector<Shard> shards;
    for (const auto& path : stores) {
        Shard s{path, readShardManifest(shardManifestPath(path)), nullptr};
        try {
            s.store = TileStore::open(path);
        } catch (const StoreError& e) {
            throw CompileError(e.what());
        }
        shards.push_back(std::move(s));
    }
    // One whole compile: the same N and fingerprint, every k once.
    const Shard& first = shards.front();
    const int count = first.manifest.shard.count;
    std::map<int, const Shard*> by_index;
    for (const Shard& s : shards) {
        if (s.manifest.shard.count != count) {
            throw CompileError(s.path.string() + ": shard " + describe(s.manifest.shard) + ", but " +
                               first.path.string() + " is one of " + std::to_string(count));
        }
        if (s.manifest.fingerprint != first.manifest.fingerprint) {
            throw CompileError(s.path.string() + ": compiled from other input or options than " + first.path.string() +
                               " (" + s.manifest.fingerprint + " vs " + first.manifest.fingerprint + ")");
        }
        if (const auto [it, inserted] = by_index.emplace(s.manifest.shard.index, &s); !inserted) {
            throw CompileError("merge: shard " + describe(s.manifest.shard) + " given twice (" +
                               it->second->path.string() + ", " + s.path.string() + ")");
        }
    }
    if (static_cast<int>(by_index.size()) != count) {
        std::string missing;
        for (int k = 0; k < count; ++k) {
            if (by_index.count(k) == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
        }
        throw CompileError("merge: shard(s) " + missing + " of " + std::to_string(count) + " missing");
    }
    // The same frame and scheme in every store (the fingerprint says the same input; this says
    // the stores are what the manifests describe).
    const StoreInfo& info = first.store->info();
    std::vector<std::pair<std::uint64_t, const Shard*>> tiles;
    for (const Shard& s : shards) {
        const StoreInfo& i = s.store->info();
        const bool same = i.format_version == info.format_version && i.origin_lat == info.origin_lat &&
                          i.origin_lon == info.origin_lon && i.scheme.worldRoot() == info.scheme.worldRoot() &&
                          i.scheme.levelCount() == info.scheme.levelCount() && i.dem_samples == info.dem_samples &&
                          i.south == info.south && i.west == info.west && i.north == info.north && i.east == info.east;
        if (!same) {
            throw CompileError(s.path.string() + ": its header (frame, tile scheme, bounds or version) differs from " +
                               first.path.string() + "'s");
        }
        const auto ids = s.store->tileIds();
        if (ids.size() != s.manifest.tiles) {
            throw CompileError(s.path.string() + ": holds " + std::to_string(ids.size()) +
                               " tiles, its manifest says " + std::to_string(s.manifest.tiles));
        }
        const ShardGrid grid = shardGridOf(info);
        for (const TileId id : ids) {
            if (tileShard(id, count, grid) != s.manifest.shard.index) {
                throw CompileError(s.path.string() + ": tile " + std::to_string(id.level) + "/" + std::to_string(id.x) +
                                   "/" + std::to_string(id.y) + " belongs to shard " +
                                   std::to_string(tileShard(id, count, grid)) + ", not " + describe(s.manifest.shard));
            }
            tiles.emplace_back(id.key(), &s);
        }
    }
    const Shard& graph_shard = *by_index.at(0);
    if (!graph_shard.manifest.graph) throw CompileError(graph_shard.path.string() + ": shard 0 has no road graph");
    // The single compile's order: level by level, by key within a level (TileId::key() sorts so).
    std::sort(tiles.begin(), tiles.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    StoreInfo out_info = info;
    StoreWriter writer(out, out_info);
    for (const auto& [key, s] : tiles) {
        const TileId id{static_cast<std::uint8_t>(key >> 56), static_cast<std::uint32_t>((key >> 28) & 0xFFFFFFF),
                        static_cast<std::uint32_t>(key & 0xFFFFFFF)};
        const auto loaded = s->store->load(id);
        if (!loaded.tile) throw CompileError(loaded.error);
        writer.addTile(*loaded.tile);
    }
    const auto graph = graph_shard.store->tryLoadGraph();
    if (!graph.ok()) throw CompileError(graph.error);
    writer.setGraph(graph.graph);
    MergeStats stats;
    stats.shards = shards.size();
    stats.tiles = tiles.size();
    stats.store_bytes = writer.finish();
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (log) {
        log("merged " + std::to_string(stats.shards) + " shards, " + std::to_string(stats.tiles) + " tiles into " +
            out.string());
    }
    return stats;
}

}  // namespace navmap::map
