// SPDX-License-Identifier: Apache-2.0
#pragma once
// The network inputs of a tile's orthoimage pixels from its layers (seed 6.6.2: "using land cover,
// elevation, climate zones [...] we generate appropriate input vectors on the CPU"): land-cover and
// climate shares from the four nearest texels or samples (bilinear weights, the top two kept),
// scalars bilinear, encoded and compressed as the trainer encodes its samples (input_encoding.h).
// GL-free; the GPU generator (render/src/gl/ortho_generator.cpp) uploads what encodeRows makes.

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/map/ortho/input_encoding.h"
#include "navmap/map/ortho/super_land_cover.h"
#include "navmap/map/tile.h"

namespace navmap::map::ortho {

/// Why a tile's layers cannot be sampled ("tile 6/33/17: ortho layer temp_dec has 1000 samples,
/// expected 1089 (33x33)"); empty when they can. Tiles read from a store are checked by its decoder
/// already; this guards tiles made elsewhere.
std::string orthoLayersProblem(const Tile& tile);

class OrthoTileSampler {
public:
    /// The tile must outlive the sampler. Throws std::invalid_argument with orthoLayersProblem()
    /// when its layers are empty or of inconsistent sizes.
    explicit OrthoTileSampler(const Tile& tile);

    /// Decoded inputs at tile-local metres (x east, y north of the tile origin).
    [[nodiscard]] OrthoPixel pixel(double x, double y) const;
    /// The super land cover texel holding the point (procedural detail, seed 6.7).
    [[nodiscard]] SuperLandCover coverAt(double x, double y) const;

    /// Compressed inputs of a size x size raster over the square [x0, x0 + extent] x [y0, y0 +
    /// extent] of the tile (pixel centres; row 0 south), rows [row0, row1), into
    /// out[(r - row0) * size + c].
    void encodeRows(double x0, double y0, double extent, int size, int row0, int row1, OrthoInput* out) const;

private:
    struct Bilinear {
        int i00, i10, i01, i11;
        float w00, w10, w01, w11;
    };
    [[nodiscard]] Bilinear gridWeights(double x, double y) const;
    [[nodiscard]] static float grid(const std::vector<std::uint8_t>& layer, const Bilinear& b,
                                    float (*decode)(std::uint8_t));

    const OrthoLayers& m_layers;
    double m_texel = 0;    // cover texel size (m)
    double m_spacing = 0;  // grid spacing (m)
};

}  // namespace navmap::map::ortho
