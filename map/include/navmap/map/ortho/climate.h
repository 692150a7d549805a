// SPDX-License-Identifier: Apache-2.0
#pragma once
// Climate zones of the synthetic orthoimages (seed 6.4 "Climate zones", 6.5 coastline
// correction and scrambling). The seed uses the Koeppen-Geiger classification of Peel et al.;
// marble-qt-data has the mean temperature and precipitation of December and July (Legates and
// Willmott), from which the 30 Koeppen-Geiger classes of Peel et al. are derived with the two
// months standing in for the year (docs/orthoimage.md "Climate").

#include <array>
#include <cstdint>
#include <vector>

#include "navmap/map/ortho/geo_grid.h"
#include "navmap/map/ortho/natural_earth.h"
#include "navmap/map/ortho/ortho_layers.h"

namespace navmap::map::ortho {

enum class ClimateClass : std::uint8_t {
    Af = 0,
    Am,
    Aw,
    BWh,
    BWk,
    BSh,
    BSk,
    Csa,
    Csb,
    Csc,
    Cwa,
    Cwb,
    Cwc,
    Cfa,
    Cfb,
    Cfc,
    Dsa,
    Dsb,
    Dsc,
    Dsd,
    Dwa,
    Dwb,
    Dwc,
    Dwd,
    Dfa,
    Dfb,
    Dfc,
    Dfd,
    ET,
    EF,
};
inline constexpr int kClimateClassCount = 30;
static_assert(kClimateClassCount == kClimateCodeCount, "the stored layer codes (ortho_layers.h)");
const char* climateName(ClimateClass c);

/// Koeppen-Geiger class (Peel et al. 2007 rules) from the mean temperatures (C) and
/// precipitation (mm per month) of December and July at latitude `lat` (summer is July north of
/// the equator, December south of it). The year is estimated from the two months: mean
/// temperature = their mean, annual precipitation = 6 times their sum.
ClimateClass classifyClimate(float t_dec, float t_jul, float p_dec, float p_jul, double lat);

/// The two largest class shares around a point (the category at the point and one from its
/// neighbourhood, seed 6.6.1), from the bilinear weights of the four nearest raster cells.
struct ClassShares {
    std::uint8_t first = 0, second = 0;
    float first_share = 1.0f, second_share = 0.0f;
};
/// Top two of up to four (class, weight) pairs; ties keep the lower class.
ClassShares topTwoShares(const std::array<std::uint8_t, 4>& classes, const std::array<float, 4>& weights);

/// The global climate-class raster on the temperature grid.
struct ClimateGrid {
    int width = 0, height = 0;
    std::vector<std::uint8_t> classes;  ///< ClimateClass per pixel, row 0 north

    [[nodiscard]] bool empty() const { return classes.empty(); }
    [[nodiscard]] ClimateClass nearest(double lat, double lon) const;
    [[nodiscard]] ClassShares shares(double lat, double lon) const;
};

inline constexpr std::uint64_t kScrambleSeed = 0x6e61766d61703665ULL;
inline constexpr int kScrambleIterations = 3;

/// Classifies every land pixel (Natural Earth land, ice shelves and glaciers at the grid's
/// resolution), scrambles the classes among neighbouring land pixels (seed 6.5: `iterations`
/// sweeps that swap each land pixel with a random land 4-neighbour, so categorical borders
/// diffuse instead of being interpolated), then grows the land classes into the water pixels
/// (coastline correction: a coast that the fine land cover calls land always finds a land class).
/// Deterministic for a given seed. All four grids must have the same size.
ClimateGrid buildClimateGrid(const GeoGrid& t_dec, const GeoGrid& t_jul, const GeoGrid& p_dec, const GeoGrid& p_jul,
                             const NaturalEarthCover& cover, std::uint64_t seed = kScrambleSeed,
                             int iterations = kScrambleIterations);

}  // namespace navmap::map::ortho
