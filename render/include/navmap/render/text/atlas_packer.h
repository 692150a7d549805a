// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shelf packing of rectangles into a texture whose height can grow.

#include <optional>
#include <vector>

namespace navmap::render::text {

struct AtlasRect {
    int x = 0, y = 0, w = 0, h = 0;
};

/// Shelf (row) packer: a rectangle goes onto the first shelf tall enough and not more than
/// 1.5x its height (fewer wasted rows), else onto a new shelf. Deterministic.
class AtlasPacker {
public:
    AtlasPacker(int width, int height);
    /// Packs a w x h rectangle (plus `padding` texels right and below); nullopt when full.
    std::optional<AtlasRect> pack(int w, int h, int padding = 1);
    /// Makes room below the existing shelves (height only grows).
    void grow(int new_height) { m_height = new_height > m_height ? new_height : m_height; }
    void clear();
    [[nodiscard]] int width() const { return m_width; }
    [[nodiscard]] int height() const { return m_height; }
    /// Rows taken by shelves so far.
    [[nodiscard]] int usedHeight() const { return m_next_y; }

private:
    struct Shelf {
        int y = 0, h = 0, x = 0;
    };
    int m_width;
    int m_height;
    int m_next_y = 0;
    std::vector<Shelf> m_shelves;
};

}  // namespace navmap::render::text
