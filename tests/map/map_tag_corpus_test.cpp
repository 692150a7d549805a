// SPDX-License-Identifier: Apache-2.0
// The area tag corpus (tests/map/data/area_tag_corpus.tsv, docs/tile-store.md "Area classes"):
// every row one small area of its own, all of them in one OSM file far enough apart, compiled by
// the real navmap-compile; the classes are read back from the store's leaf tiles at each area's
// centre and compared with the row's expected class, or with nothing where the schema draws none.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "map_test_util.h"
#include "navmap/map/compile/compiler.h"
#include "navmap/map/feature_classes.h"
#include "navmap/map/tile_store.h"

using namespace navmap::map;
using navmap::map::test::ScratchDir;

namespace {

struct Row {
    int line = 0;
    std::string kind;  // way, rel, onwater, mpwater
    std::vector<std::pair<std::string, std::string>> tags;
    std::string expected;  // an areaClassName, or "none"
};

std::vector<Row> readCorpus(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    std::vector<Row> rows;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> cols;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, '\t');) cols.push_back(c);
        EXPECT_EQ(cols.size(), 4u) << path << ":" << n;
        if (cols.size() != 4) continue;
        Row r;
        r.line = n;
        r.kind = cols[0];
        r.expected = cols[2];
        std::stringstream ts(cols[1]);
        for (std::string kv; std::getline(ts, kv, ';');) {
            const auto eq = kv.find('=');
            EXPECT_NE(eq, std::string::npos) << path << ":" << n << ": " << kv;
            if (eq != std::string::npos) r.tags.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
        }
        rows.push_back(std::move(r));
    }
    return rows;
}

std::optional<AreaClass> classNamed(const std::string& name) {
    for (int c = 0; c < kAreaClassCount; ++c) {
        if (areaClassName(static_cast<AreaClass>(c)) == name) return static_cast<AreaClass>(c);
    }
    return std::nullopt;
}

constexpr double kSpacing = 0.006;  // degrees between the rows' centres
constexpr int kColumns = 20;

struct Centre {
    double lat, lon;
};
Centre centreOf(std::size_t i) {
    return {43.003 + kSpacing * static_cast<double>(i / kColumns),
            7.003 + kSpacing * static_cast<double>(i % kColumns)};
}

/// The OSM XML of all rows: row i has node ids from 1000 i, way ids from 1000 i, relation id i + 1.
std::string corpusOsm(const std::vector<Row>& rows) {
    std::ostringstream o;
    o.precision(9);
    o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<osm version=\"0.6\" generator=\"test\">\n";
    std::ostringstream ways, rels;
    auto square = [&](long id, Centre c, double half, const std::vector<std::pair<std::string, std::string>>& tags) {
        const double dlat[4] = {-half, -half, half, half}, dlon[4] = {-half, half, half, -half};
        for (int k = 0; k < 4; ++k)
            o << " <node id=\"" << id + k << "\" version=\"1\" lat=\"" << c.lat + dlat[k] << "\" lon=\""
              << c.lon + dlon[k] << "\"/>\n";
        ways << " <way id=\"" << id << "\" version=\"1\">";
        for (int k = 0; k < 5; ++k) ways << "<nd ref=\"" << id + k % 4 << "\"/>";
        for (const auto& [k, v] : tags) ways << "<tag k=\"" << k << "\" v=\"" << v << "\"/>";
        ways << "</way>\n";
    };
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        const long base = 1000L * static_cast<long>(i + 1);
        const Centre c = centreOf(i);
        if (r.kind == "way") {
            square(base, c, 0.001, r.tags);
        } else if (r.kind == "onwater") {
            square(base, c, 0.0015, {{"natural", "water"}});
            square(base + 10, c, 0.001, r.tags);
        } else if (r.kind == "rel" || r.kind == "mpwater") {
            square(base, c, 0.001, {});
            rels << " <relation id=\"" << i + 1 << "\" version=\"1\"><member type=\"way\" ref=\"" << base
                 << "\" role=\"outer\"/>";
            if (r.kind == "mpwater") {
                square(base + 10, c, 0.0005, {{"natural", "water"}});
                rels << "<member type=\"way\" ref=\"" << base + 10 << "\" role=\"inner\"/>";
            }
            for (const auto& [k, v] : r.tags) rels << "<tag k=\"" << k << "\" v=\"" << v << "\"/>";
            rels << "</relation>\n";
        } else {
            ADD_FAILURE() << "line " << r.line << ": unknown kind " << r.kind;
        }
    }
    o << ways.str() << rels.str() << "</osm>\n";
    return o.str();
}

/// The classes of the store's leaf-tile areas under a point, lowest drawn first.
std::vector<AreaClass> classesAt(const TileStore& store, double lat, double lon) {
    const PlanarPoint p = store.projection().forward(lat, lon);
    const auto id = store.scheme().tileAt(store.scheme().leafLevel(), p);
    if (!id) return {};
    const auto res = store.load(*id);
    if (!res.tile) return {};
    const Tile& t = *res.tile;
    const LocalPoint local{static_cast<float>(p.x - t.origin_x), static_cast<float>(p.y - t.origin_y)};
    std::vector<AreaClass> out;
    for (const Area& a : t.areas) {
        const auto& poly = a.polygon;
        for (std::size_t i = 0; i + 2 < poly.indices.size(); i += 3) {
            const LocalPoint u = poly.vertices[poly.indices[i]], v = poly.vertices[poly.indices[i + 1]],
                             w = poly.vertices[poly.indices[i + 2]];
            auto side = [&](LocalPoint s, LocalPoint e) {
                return (e.x - s.x) * (local.y - s.y) - (e.y - s.y) * (local.x - s.x);
            };
            const float s0 = side(u, v), s1 = side(v, w), s2 = side(w, u);
            if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) {
                out.push_back(a.cls);
                break;
            }
        }
    }
    std::stable_sort(out.begin(), out.end(),
                     [](AreaClass a, AreaClass b) { return areaDrawOrder(a) < areaDrawOrder(b); });
    return out;
}

std::string names(const std::vector<AreaClass>& classes) {
    std::string s;
    for (AreaClass c : classes) s += (s.empty() ? "" : ",") + std::string(areaClassName(c));
    return s.empty() ? "none" : s;
}

}  // namespace

TEST(AreaTagCorpus, EveryRowCompilesToItsSchemaClassOrToNothing) {
    const std::vector<Row> rows = readCorpus(NAVMAP_TAG_CORPUS);
    ASSERT_GE(rows.size(), 150u);
    ScratchDir dir("tag-corpus");
    std::ofstream(dir / "corpus.osm") << corpusOsm(rows);
    CompileOptions opt;
    opt.osm = dir / "corpus.osm";
    opt.out = dir / "corpus.navmap";
    opt.leaf_tile_m = 1000;
    compileStore(opt);
    const auto store = TileStore::open(opt.out);

    int passed = 0;
    std::map<std::string, int> per_class;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        std::string tags;
        for (const auto& [k, v] : r.tags) tags += (tags.empty() ? "" : ";") + k + "=" + v;
        const std::string where = "corpus line " + std::to_string(r.line) + " (" + r.kind + " " + tags + ")";
        const auto expected = classNamed(r.expected);
        ASSERT_TRUE(expected || r.expected == "none") << where << ": no class " << r.expected;
        const Centre c = centreOf(i);
        const std::vector<AreaClass> at = classesAt(*store, c.lat, c.lon);
        bool ok = false;
        if (r.kind == "onwater") {
            // The row's area inside a larger water: the water under it, the class on top as expected.
            ok = !at.empty() && at.back() == *expected && std::count(at.begin(), at.end(), AreaClass::Water) >= 1 &&
                 at.size() <= 2;
        } else if (r.kind == "mpwater") {
            // On the ring between the outer and the inner way: the class; in the hole: the water only.
            const std::vector<AreaClass> ring = classesAt(*store, c.lat + 0.00075, c.lon);
            ok = at == std::vector<AreaClass>{AreaClass::Water} && ring == std::vector<AreaClass>{*expected};
            EXPECT_TRUE(ok) << where << ": ring " << names(ring) << ", hole " << names(at) << "; expected ring "
                            << r.expected << ", hole water";
            passed += ok ? 1 : 0;
            continue;
        } else {
            ok = expected ? at == std::vector<AreaClass>{*expected} : at.empty();
        }
        EXPECT_TRUE(ok) << where << ": got " << names(at) << ", expected " << r.expected;
        passed += ok ? 1 : 0;
        ++per_class[r.expected];
    }
    EXPECT_EQ(passed, static_cast<int>(rows.size()));
    // Every class the schema writes from tags is in the corpus, and so are many undrawn tags.
    for (const char* name :
         {"water", "wetland", "glacier", "forest", "scrub", "grass", "farmland", "rock", "residential", "commercial",
          "industrial", "park", "sport", "cemetery", "military", "pier", "harbour"}) {
        EXPECT_GE(per_class[name], 1) << name;
    }
    EXPECT_GE(per_class["none"], 100);

    // Bays, straits, mountain ranges and regions keep their names as labels, never as areas.
    std::set<std::string> labels;
    for (const auto& id : store->tileIds()) {
        const auto res = store->load(id);
        ASSERT_TRUE(res.tile) << res.error;
        for (const Label& l : res.tile->labels) labels.insert(l.name);
        for (const Area& a : res.tile->areas) {
            EXPECT_NE(a.cls, AreaClass::Other) << id.toString();
            EXPECT_NE(a.name, "Test Range") << id.toString();
            EXPECT_NE(a.name, "Test Bay") << id.toString();
        }
    }
    for (const char* name : {"Test Bay", "Test Strait", "Test Gulf", "Test Range", "Test Region", "Test Island"})
        EXPECT_EQ(labels.count(name), 1u) << name;
}
