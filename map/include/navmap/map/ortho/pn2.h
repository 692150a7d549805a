// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reader of Marble's .pn2 polygon files (the Natural Earth 1:50m layers Debian's marble-qt-data
// ships under /usr/share/marble/data/naturalearth/), used as global land-cover input of the
// synthetic orthoimages (seed 6.4, 6.5).
//
// The format, as the files are laid out (big-endian, Qt QDataStream encoding):
//
//   header   u8 version (2), u32 record count, u8 has-colour flag (bool)
//   record   u8 kind, u32 id, [u8 colour index: only when the header's flag is set, for kinds
//            other than 3 and not for the parts of a multi-geometry],
//            then for kind 4 (multi-geometry): u8 part count, and the parts (inner boundaries
//            included) follow as records of their own with the same id (they count towards the
//            header's record count, the multi-geometry record itself does not);
//            for kinds 0..3: u32 node count, then per node
//              i16 lat, i16 lon (1/120 degree), i16 child count, then child count times
//              i8 dlat, i8 dlon (1/120 degree, relative to that node, not to the previous child)
//   kinds    0 line string, 1 linear ring, 2 outer boundary, 3 inner boundary (a hole of the outer
//            boundary before it), 4 multi-geometry
//
// Version 1 files (no kind byte) are refused. Every file in the Debian package is read to its
// last byte by this layout (tests/map/ortho/pn2_test.cpp).
// Hand-written: Marble's own reader is a Qt plugin of libmarblewidget; no library reads the
// format without Qt and Marble's runtime.

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "navmap/common/geo_coordinate.h"

namespace navmap::map::ortho {

/// Raised when a .pn2 file cannot be read; the message names the file, the byte offset and the
/// problem ("ne_50m_land.pn2: truncated at byte 1234 (node 5 of record 17)").
class Pn2Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// One polygon: outer ring and holes (rings open: the last point is not repeated), WGS84 degrees.
struct Pn2Polygon {
    std::uint32_t id = 0;
    std::vector<GeoCoordinate> outer;
    std::vector<std::vector<GeoCoordinate>> holes;
};

struct Pn2File {
    std::vector<Pn2Polygon> polygons;               ///< kinds 2 (+3) and 1
    std::vector<std::vector<GeoCoordinate>> lines;  ///< kind 0
    std::size_t records = 0;                        ///< records read (the header's count)
};

/// Reads a whole file; throws Pn2Error.
Pn2File readPn2(const std::filesystem::path& path);
/// Parses bytes; `name` names the source in errors.
Pn2File parsePn2(const std::vector<std::uint8_t>& bytes, const std::string& name);

}  // namespace navmap::map::ortho
