// SPDX-License-Identifier: Apache-2.0
#include "bounded_inflate.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace navmap::map::detail {

namespace {

constexpr std::size_t kFirstPiece = std::size_t{64} << 10;
constexpr std::size_t kMaxFeed = std::numeric_limits<uInt>::max();

}  // namespace

std::uint64_t maxDeflatedBytes(std::uint64_t raw_bytes) { return compressBound(static_cast<uLong>(raw_bytes)); }

bool inflateBounded(std::span<const std::uint8_t> stored, std::uint64_t raw_size, std::vector<std::uint8_t>& raw,
                    std::string& problem, std::size_t prefix_bytes, const PrefixCheck& check) {
    raw.clear();
    if (raw_size > maxInflatedBytes(stored.size())) {
        problem = "declares " + std::to_string(raw_size) + " bytes from " + std::to_string(stored.size()) +
                  " compressed, more than zlib's 1032:1 allows";
        return false;
    }
    if (raw_size > std::numeric_limits<std::size_t>::max() / 2) {
        problem = "declares " + std::to_string(raw_size) + " bytes, more than this machine can address";
        return false;
    }
    auto fail = [&](std::string why) {
        raw.clear();
        raw.shrink_to_fit();
        problem = std::move(why);
        return false;
    };
    z_stream z{};
    if (inflateInit(&z) != Z_OK) return fail("decompression failed (zlib could not start)");
    struct End {
        z_stream* z;
        ~End() { inflateEnd(z); }
    } end{&z};

    const auto want = static_cast<std::size_t>(raw_size);
    raw.resize(std::min(want, kFirstPiece));
    std::size_t in_pos = 0, out_pos = 0;
    bool checked = !check;
    int rc = Z_OK;
    for (;;) {
        if (z.avail_in == 0 && in_pos < stored.size()) {
            const std::size_t n = std::min(stored.size() - in_pos, kMaxFeed);
            z.next_in = const_cast<Bytef*>(stored.data() + in_pos);  // zlib's API is not const-correct; it only reads
            z.avail_in = static_cast<uInt>(n);
            in_pos += n;
        }
        if (out_pos == raw.size()) {
            if (raw.size() == want) {
                // Full: the stream must end here. One more byte of room tells an end from a
                // stream that would go on past the declared size.
                std::uint8_t extra = 0;
                z.next_out = &extra;
                z.avail_out = 1;
                rc = inflate(&z, Z_NO_FLUSH);
                if (rc == Z_STREAM_END && z.avail_out == 1) break;
                if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_MEM_ERROR)
                    return fail("decompression failed (damaged stream)");
                if (z.avail_out == 0)
                    return fail("decompression failed (inflates to more than the declared " + std::to_string(want) +
                                " bytes)");
                if (z.avail_in == 0 && in_pos == stored.size())
                    return fail("decompression failed (the stream ends without its end mark)");
                continue;
            }
            raw.resize(std::min(want, std::max(raw.size() * 2, kFirstPiece)));
        }
        const std::size_t room = std::min(raw.size() - out_pos, kMaxFeed);
        z.next_out = raw.data() + out_pos;
        z.avail_out = static_cast<uInt>(room);
        rc = inflate(&z, Z_NO_FLUSH);
        out_pos += room - z.avail_out;
        if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_MEM_ERROR)
            return fail("decompression failed (damaged stream)");
        if (!checked && (out_pos >= prefix_bytes || rc == Z_STREAM_END)) {
            checked = true;
            std::string why;
            if (!check(std::span<const std::uint8_t>(raw.data(), std::min(out_pos, raw.size())), why)) return fail(why);
        }
        if (rc == Z_STREAM_END) {
            if (out_pos != want) {
                return fail("decompression failed (inflates to " + std::to_string(out_pos) + " of the declared " +
                            std::to_string(want) + " bytes)");
            }
            break;
        }
        if (rc == Z_BUF_ERROR && z.avail_in == 0 && in_pos == stored.size())
            return fail("decompression failed (the stream ends without its end mark)");
    }
    if (!checked) {
        std::string why;
        if (!check(std::span<const std::uint8_t>(raw.data(), out_pos), why)) return fail(why);
    }
    return true;
}

}  // namespace navmap::map::detail
