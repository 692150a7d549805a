// SPDX-License-Identifier: Apache-2.0
// The bounded compile's multipolygon manager, which keeps member ways in a spill file, gives the
// same areas in the same order, to the byte, as libosmium's MultipolygonManager that keeps them
// in memory: complete, incomplete and unwanted relations, a way shared by two relations, a
// closed way that is an area of its own.
#include <gtest/gtest.h>

// GCC 12 reports a false -Wstringop-overread inside libosmium's area builder (as in compile_read.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif

#include <osmium/area/multipolygon_manager.hpp>
#include <osmium/builder/attr.hpp>
#include <osmium/osm/area.hpp>
#include <osmium/visitor.hpp>

#include "map_test_util.h"
#include "multipolygon_spill.h"

using namespace navmap::map::detail;
using navmap::map::test::ScratchDir;
using namespace osmium::builder::attr;  // NOLINT: the builder's attribute vocabulary

namespace {

osmium::NodeRef at(osmium::object_id_type id, double lon, double lat) { return {id, osmium::Location{lon, lat}}; }

osmium::TagsFilter areaFilter() {  // as compile_read.cpp
    osmium::TagsFilter filter{false};
    for (const char* key : {"building", "landuse", "natural", "leisure", "waterway", "amenity", "place"}) {
        filter.add_rule(true, osmium::TagMatcher{key});
    }
    return filter;
}

struct Input {
    osmium::memory::Buffer relations{1 << 16, osmium::memory::Buffer::auto_grow::yes};
    osmium::memory::Buffer ways{1 << 16, osmium::memory::Buffer::auto_grow::yes};
};

Input input() {
    Input in;
    using osmium::item_type;
    // A forest with a clearing: the outer ring in two ways (11, 15), the inner ring closed (10).
    osmium::builder::add_relation(in.relations, _id(100), _tag("type", "multipolygon"), _tag("landuse", "forest"),
                                  _member(item_type::way, 11, "outer"), _member(item_type::way, 15, "outer"),
                                  _member(item_type::way, 10, "inner"));
    // A lake with a member missing from the input (cut off by the extract): no area.
    osmium::builder::add_relation(in.relations, _id(101), _tag("type", "multipolygon"), _tag("natural", "water"),
                                  _member(item_type::way, 13, "outer"), _member(item_type::way, 99, "outer"));
    // A park with a node member (ignored), and an island sharing the park's way.
    osmium::builder::add_relation(in.relations, _id(102), _tag("type", "multipolygon"), _tag("leisure", "park"),
                                  _member(item_type::node, 1, "label"), _member(item_type::way, 14, "outer"));
    // Not a multipolygon, a multipolygon without a wanted tag, and a boundary.
    osmium::builder::add_relation(in.relations, _id(103), _tag("type", "route"), _member(item_type::way, 11, ""));
    osmium::builder::add_relation(in.relations, _id(104), _tag("type", "boundary"), _tag("place", "island"),
                                  _member(item_type::way, 14, "outer"));
    osmium::builder::add_relation(in.relations, _id(105), _tag("type", "multipolygon"), _tag("name", "x"),
                                  _member(item_type::way, 13, "outer"));

    // Ways in id order (as libosmium requires): the forest completes last, a building between.
    osmium::builder::add_way(
        in.ways, _id(10),
        _nodes({at(5, 1.2, 42.2), at(6, 1.4, 42.2), at(7, 1.4, 42.4), at(8, 1.2, 42.4), at(5, 1.2, 42.2)}));
    osmium::builder::add_way(in.ways, _id(11), _nodes({at(1, 1.0, 42.0), at(2, 1.6, 42.0), at(3, 1.6, 42.6)}));
    osmium::builder::add_way(
        in.ways, _id(12), _tag("building", "yes"),
        _nodes({at(20, 2.0, 42.0), at(21, 2.01, 42.0), at(22, 2.01, 42.01), at(23, 2.0, 42.01), at(20, 2.0, 42.0)}));
    osmium::builder::add_way(in.ways, _id(13), _nodes({at(30, 3.0, 42.0), at(31, 3.1, 42.0), at(32, 3.1, 42.1)}));
    osmium::builder::add_way(
        in.ways, _id(14),
        _nodes({at(40, 4.0, 42.0), at(41, 4.1, 42.0), at(42, 4.1, 42.1), at(43, 4.0, 42.1), at(40, 4.0, 42.0)}));
    osmium::builder::add_way(in.ways, _id(15), _nodes({at(3, 1.6, 42.6), at(4, 1.0, 42.6), at(1, 1.0, 42.0)}));
    return in;
}

/// The bytes of every area buffer the manager hands out, in order, and the areas' ids.
struct Output {
    std::vector<std::uint8_t> bytes;
    std::vector<osmium::object_id_type> ids;
};

template <class Manager>
Output run(Manager& manager, Input& in) {
    Output out;
    osmium::apply(in.relations, manager);
    manager.prepare_for_lookup();
    auto& handler = manager.handler([&](osmium::memory::Buffer&& buffer) {
        out.bytes.insert(out.bytes.end(), buffer.data(), buffer.data() + buffer.committed());
        for (const auto& area : buffer.select<osmium::Area>()) out.ids.push_back(area.id());
    });
    osmium::apply(in.ways, handler);
    return out;
}

}  // namespace

TEST(DiskMultipolygons, GiveLibosmiumsAreasInItsOrderToTheByte) {
    Input a = input(), b = input();
    osmium::area::Assembler::config_type config;
    osmium::area::MultipolygonManager<osmium::area::Assembler> in_memory{config, areaFilter()};
    const Output expected = run(in_memory, a);

    ScratchDir dir("multipolygon-spill");
    DiskMultipolygonManager on_disk{config, areaFilter(), dir / "ways.spill"};
    const Output got = run(on_disk, b);

    // The building (way 12: area 24), the island and the park (relations 104 and 102, both
    // completed by way 14, in the order of their member's place), the forest (relation 100:
    // area 201); not the lake.
    EXPECT_EQ(expected.ids, (std::vector<osmium::object_id_type>{24, 209, 205, 201}));
    EXPECT_EQ(got.ids, expected.ids);
    EXPECT_EQ(got.bytes, expected.bytes);
    // Ways wanted by a relation went to the file, once each (10, 11, 13, 14, 15).
    EXPECT_EQ(on_disk.memberWays(), 5u);
    EXPECT_EQ(on_disk.completeRelations(), 3u);
}
