// SPDX-License-Identifier: Apache-2.0
#pragma once
// AttributionOverlay: the map data attribution ("© OpenStreetMap contributors") in a corner of a
// profile's frames. ODbL 4.3 asks for the attribution wherever the map is shown, in a manner
// reasonable for the medium; a profile switches it with `attribution` (docs/navmapd.md). The
// text is laid out once per frame size with the label text engine (FreeType + HarfBuzz, SDF
// atlas) and kept as a coverage mask; each published frame gets it composited on the CPU (a few
// thousand pixels, well under 0.1 ms), so it is the same on every renderer, the no-op one included;
// a dma-buf frame gets the same blend on the GPU (premultiplied()).

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/render/image.h"

namespace navmap::render::text {
class TextEngine;
}

namespace navmap::daemon {

class AttributionOverlay {
public:
    /// The map data attribution of the shipped data (data/ATTRIBUTION.md).
    static constexpr const char* kOsmAttribution = "\u00a9 OpenStreetMap contributors";

    /// Lays `text` out for frames of `width` x `height` (text size 3% of the height, 10..16 px),
    /// bottom right, white on a translucent dark box. Uses `engine` only here.
    AttributionOverlay(render::text::TextEngine& engine, const std::string& text, int width, int height);

    /// Blends the box and the text into an RGBA8 frame of the size given at construction
    /// (`stride` bytes per row). Any thread.
    void apply(std::uint8_t* rgba, int stride) const;
    /// The same blend as premultiplied RGBA pixels of the box (boxWidth() x boxHeight()), for
    /// the GPU to blend over a frame that never comes to the CPU (a dma-buf frame): "over" with
    /// these gives apply()'s result within rounding.
    render::Image premultiplied() const;

    /// The box in frame pixels (for tests and logs).
    int x() const noexcept { return m_x; }
    int y() const noexcept { return m_y; }
    int boxWidth() const noexcept { return m_w; }
    int boxHeight() const noexcept { return m_h; }

private:
    int m_width = 0, m_height = 0;
    int m_x = 0, m_y = 0, m_w = 0, m_h = 0;  // the box
    std::vector<std::uint8_t> m_coverage;    // m_w x m_h, text coverage 0..255
};

}  // namespace navmap::daemon
