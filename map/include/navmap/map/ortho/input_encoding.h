// SPDX-License-Identifier: Apache-2.0
#pragma once
// Input vectors of the orthoimage network (seed 6.6.1 "Encoding of input vectors", Table 6.3
// for the inputs at hand). One node per category of a class-based input (land cover, climate),
// one node per scalar input. Class-based inputs activate at most two nodes: the category at the
// pixel and one from its neighbourhood, weighted by their shares (ClassShares), so categories
// blend at their borders. A pixel's vector is stored compressed (seed 6.6.2): only the active
// nodes, as (node index, value) pairs of bytes, the value being the input times 255. Training,
// the CPU reference and the shader all read these same bytes.
//
// Nodes (kOrthoEncodingVersion 1):
//   0..6    global land cover (GlobalCover), the super land cover's trainedAs() class; two
//   7..36   climate class (ClimateClass); two
//   37      elevation: max(h, 0) / 6000 m (bathymetry is not an input, seed 6.6.1)
//   38, 39  temperature of December, July: (T + 70 C) / 115 C
//   40, 41  precipitation of December, July: sqrt(P / 2048 mm)
//   42      city lights: 0 (none) .. 1
// Slope and aspect are not inputs (seed 6.6.1: the network would learn the satellite image's
// lighting); relief shading is added when drawing.

#include <array>
#include <cstdint>

#include "navmap/map/ortho/climate.h"
#include "navmap/map/ortho/natural_earth.h"

namespace navmap::map::ortho {

inline constexpr std::uint32_t kOrthoEncodingVersion = 1;
inline constexpr int kCoverNode = 0;
inline constexpr int kClimateNode = kCoverNode + kGlobalCoverCount;       // 7
inline constexpr int kElevationNode = kClimateNode + kClimateClassCount;  // 37
inline constexpr int kTempDecNode = kElevationNode + 1;
inline constexpr int kTempJulNode = kElevationNode + 2;
inline constexpr int kPrecipDecNode = kElevationNode + 3;
inline constexpr int kPrecipJulNode = kElevationNode + 4;
inline constexpr int kLightsNode = kElevationNode + 5;
inline constexpr int kOrthoInputs = kLightsNode + 1;  // n = 43
/// Input types m (land cover, climate, elevation, 2 temperatures, 2 precipitations, lights).
inline constexpr int kOrthoInputTypes = 8;
/// Active nodes at most: two per class-based type, one per scalar.
inline constexpr int kOrthoActive = 2 + 2 + 6;

/// The decoded inputs of one pixel.
struct OrthoPixel {
    ClassShares cover;    ///< GlobalCover shares
    ClassShares climate;  ///< ClimateClass shares
    float elevation_m = 0;
    float temp_dec_c = 0, temp_jul_c = 0;
    float precip_dec_mm = 0, precip_jul_mm = 0;
    float lights = 0;  ///< 0..1
};

/// A compressed input vector: kOrthoActive (node, value) byte pairs; pairs with value 0 add
/// nothing.
struct OrthoInput {
    std::array<std::uint8_t, 2 * kOrthoActive> pairs{};
    [[nodiscard]] int node(int k) const { return pairs[static_cast<std::size_t>(2 * k)]; }
    [[nodiscard]] float value(int k) const { return pairs[static_cast<std::size_t>(2 * k + 1)] / 255.0f; }
    friend bool operator==(const OrthoInput&, const OrthoInput&) = default;
};

/// Quantizes an input in [0, 1] to its byte.
std::uint8_t quantizeInput(float v);
OrthoInput encodeInput(const OrthoPixel& p);
/// The full vector of n inputs (tests, training diagnostics).
std::array<float, kOrthoInputs> expandInput(const OrthoInput& in);

}  // namespace navmap::map::ortho
