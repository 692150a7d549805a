// SPDX-License-Identifier: Apache-2.0
#include "navmap/render/image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace navmap::render {

bool writePng(const std::filesystem::path& path, const Image& image, std::string* error) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) {
        if (error) *error = path.string() + ": " + OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
    if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.rgba.data()) ||
        !out->close()) {
        if (error) *error = path.string() + ": " + out->geterror();
        return false;
    }
    return true;
}

bool readImage(const std::filesystem::path& path, Image* image, std::string* error) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        if (error) *error = path.string() + ": " + OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    Image result(spec.width, spec.height);
    // Read the file's own channels and expand them: asking OIIO for 4 channels of a 3-channel
    // file (a browser's screenshot) packs 3 bytes per pixel into the 4-byte layout.
    const int channels = std::clamp(spec.nchannels, 1, 4);
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(spec.width) * spec.height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data())) {
        if (error) *error = path.string() + ": " + in->geterror();
        return false;
    }
    for (std::size_t i = 0, n = static_cast<std::size_t>(spec.width) * spec.height; i < n; ++i) {
        const std::uint8_t* src = &pixels[i * channels];
        std::uint8_t* dst = &result.rgba[i * 4];
        dst[0] = src[0];
        dst[1] = channels >= 3 ? src[1] : src[0];  // grey (and grey + alpha) to RGB
        dst[2] = channels >= 3 ? src[2] : src[0];
        dst[3] = channels == 4 ? src[3] : channels == 2 ? src[1] : 255;
    }
    *image = std::move(result);
    return true;
}

}  // namespace navmap::render
