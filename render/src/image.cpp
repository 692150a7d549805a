#include "navmap/render/image.h"

#include <OpenImageIO/imageio.h>

#include <memory>

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
    // Ask for 4 channels; OIIO fills missing ones with 0, so set alpha afterwards when absent.
    if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, result.rgba.data())) {
        if (error) *error = path.string() + ": " + in->geterror();
        return false;
    }
    if (spec.nchannels < 4) {
        for (std::size_t i = 3; i < result.rgba.size(); i += 4) result.rgba[i] = 255;
    }
    if (spec.nchannels < 3) {
        for (std::size_t i = 0; i < result.rgba.size(); i += 4) result.rgba[i + 1] = result.rgba[i + 2] = result.rgba[i];
    }
    *image = std::move(result);
    return true;
}

}  // namespace navmap::render
