// SPDX-License-Identifier: Apache-2.0
#pragma once
// CPU-side RGBA images: what readback produces and what golden tests compare. The file functions
// (writePng, readImage) are in the library navmap_image_io (OpenImageIO): link it where images are
// read or written; the renderer itself does not.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace navmap::render {

/// An 8-bit RGBA image, rows top to bottom, tightly packed (stride = 4 * width).
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0) {}

    [[nodiscard]] bool empty() const { return rgba.empty(); }
    [[nodiscard]] const std::uint8_t* pixel(int x, int y) const {
        return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
    }
    [[nodiscard]] std::uint8_t* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

/// Writes a PNG through OpenImageIO. Returns false and sets *error ("<path>: <reason>") on failure.
[[nodiscard]] bool writePng(const std::filesystem::path& path, const Image& image, std::string* error);

/// Reads any image OpenImageIO understands into RGBA8 (alpha 255 where the file has none).
/// Returns false and sets *error on failure.
[[nodiscard]] bool readImage(const std::filesystem::path& path, Image* image, std::string* error);

}  // namespace navmap::render
