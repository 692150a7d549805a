// SPDX-License-Identifier: Apache-2.0
#pragma once
// The orthoimage network (seed 6.6.1): a multilayer perceptron with one hidden layer of
// sigmoid neurons and three linear outputs (R, G, B in [0, 1], sRGB as in the Blue Marble
// training target), and its weights file. GL-free: the CPU reference of the shader and the
// trainer use it.
//
// Weights file (docs/orthoimage.md "Weights file"), little-endian:
//   0  char[8] "NAVMAPNN"        36 u32 reserved (0)
//   8  u32 file format version 1 40 u32 epochs
//  12  u32 header size (64)      44 u32 training samples
//  16  u32 input encoding version (kOrthoEncodingVersion)
//  20  u32 inputs n              48 f32 held-out mean CIE76 delta E (0: not measured)
//  24  u32 hidden h              52 u32 payload bytes (4 * (n h + h + 3 h + 3))
//  28  u32 outputs (3)           56 u32 CRC32 of the payload
//  32  u32 training seed         60 u32 CRC32 of bytes 0..59
//  64  f32 w0[n][h] (row per input), f32 b0[h], f32 w1[h][3] (row per hidden neuron), f32 b1[3]

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "navmap/map/ortho/input_encoding.h"

namespace navmap::map::ortho {

/// Raised when a weights file cannot be used; the message names the file and the problem
/// ("mlp.nnw: truncated: 812 of 8332 bytes").
class OrthoNetworkError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct OrthoTrainingInfo {
    std::uint32_t seed = 0;
    std::uint32_t epochs = 0;
    std::uint32_t samples = 0;
    float held_out_delta_e = 0.0f;
};

struct OrthoNetwork {
    int inputs = kOrthoInputs;
    int hidden = kOrthoInputs;
    std::vector<float> w0;  ///< inputs x hidden
    std::vector<float> b0;  ///< hidden
    std::vector<float> w1;  ///< hidden x 3
    std::array<float, 3> b1{};
    OrthoTrainingInfo info;

    /// Zero weights of the given shape.
    static OrthoNetwork zeros(int inputs, int hidden);
    [[nodiscard]] bool empty() const { return w0.empty(); }

    /// Forward pass over a compressed input (eq. 6.1-6.3): only the active rows of w0.
    [[nodiscard]] std::array<float, 3> forward(const OrthoInput& in) const;
    /// The same with the hidden activations (training).
    std::array<float, 3> forward(const OrthoInput& in, std::vector<float>& hidden_out) const;
    /// RGBA8 as the shader writes it: each channel clamped to [0, 1] and rounded.
    [[nodiscard]] std::array<std::uint8_t, 3> color(const OrthoInput& in) const;
};

inline float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

/// Serializes to the weights file format.
std::vector<std::uint8_t> encodeNetwork(const OrthoNetwork& net);
/// Parses a weights file; `name` names it in errors. Checks magic, versions, sizes, both
/// checksums, that the shape matches this build's input encoding, and that every weight is finite.
OrthoNetwork decodeNetwork(const std::vector<std::uint8_t>& bytes, const std::string& name);
/// Reads and decodes a weights file: a regular file (opened without blocking: a FIFO or a device
/// is refused, named) no longer than the format allows (192,588 bytes), checked before it is read.
OrthoNetwork loadNetwork(const std::filesystem::path& path);
/// Writes atomically (temporary file, rename); throws OrthoNetworkError.
void saveNetwork(const OrthoNetwork& net, const std::filesystem::path& path);

}  // namespace navmap::map::ortho
