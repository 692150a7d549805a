// SPDX-License-Identifier: Apache-2.0
#pragma once
// Decompression by plausibility (private to navmap_map): the sizes a store declares for a zlib
// stream are checked against the stored size and zlib's own limit before anything is allocated,
// and the stream is inflated in pieces, its output growing only with what it really inflates to.
// A header that lies about the raw size, or a small "zlib bomb", costs what it inflates to before
// it is caught, never what it claims; a check on the first bytes (a payload's magic) stops a
// stream of the wrong content after its first piece.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace navmap::map::detail {

/// zlib's maximum compression ratio (deflate codes a 258-byte match in 2 bits at best: zlib's
/// "technical details", 1032:1). Real data stays far below; a declared raw size above
/// stored x 1032 cannot be true.
inline constexpr std::uint64_t kZlibMaxRatio = 1032;

/// The most bytes `stored_bytes` of zlib data can inflate to.
constexpr std::uint64_t maxInflatedBytes(std::uint64_t stored_bytes) { return stored_bytes * kZlibMaxRatio; }

/// The most bytes zlib (compress2, or deflate with its settings) makes of `raw_bytes`: zlib's
/// compressBound. A stored size above it for a declared raw size cannot be true either.
std::uint64_t maxDeflatedBytes(std::uint64_t raw_bytes);

/// Checks the first bytes of the output (at least the prefix length asked for, fewer only when
/// the whole output is shorter); false with a problem ("not a road graph (bad magic)").
using PrefixCheck = std::function<bool(std::span<const std::uint8_t> head, std::string& problem)>;

/// Inflates `stored` (zlib format), which must inflate to exactly `raw_size` bytes, into `raw`.
/// The output grows in pieces (the first of at most 64 KiB, then doubling, never past raw_size);
/// `check`, when given, sees the first `prefix_bytes` as soon as they are out. False, with
/// `problem` set and `raw` emptied, when raw_size is more than zlib can make of the stored bytes,
/// the stream is damaged, ends short or runs past raw_size, or the check refuses it.
bool inflateBounded(std::span<const std::uint8_t> stored, std::uint64_t raw_size, std::vector<std::uint8_t>& raw,
                    std::string& problem, std::size_t prefix_bytes = 0, const PrefixCheck& check = {});

}  // namespace navmap::map::detail
