// SPDX-License-Identifier: Apache-2.0
#pragma once
// Little-endian byte writer/reader with LEB128 varints and zigzag deltas, used by the tile
// codec, the store header/index and the road graph. Private to navmap_map.
// Hand-written: no Debian package offers a small bounds-checked LE codec (protozero is
// protobuf-shaped and would force a schema on the store).

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace navmap::map::detail {

inline std::uint64_t zigzag(std::int64_t v) {
    return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}
inline std::int64_t unzigzag(std::uint64_t v) {
    return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1);
}

class ByteWriter {
public:
    std::vector<std::uint8_t>& bytes() { return m_bytes; }
    [[nodiscard]] std::size_t size() const { return m_bytes.size(); }

    void u8(std::uint8_t v) { m_bytes.push_back(v); }
    void u16(std::uint16_t v) { fixed(v); }
    void u32(std::uint32_t v) { fixed(v); }
    void u64(std::uint64_t v) { fixed(v); }
    void i64(std::int64_t v) { fixed(static_cast<std::uint64_t>(v)); }
    void f32(float v) {
        std::uint32_t u;
        std::memcpy(&u, &v, 4);
        fixed(u);
    }
    void f64(double v) {
        std::uint64_t u;
        std::memcpy(&u, &v, 8);
        fixed(u);
    }
    void varint(std::uint64_t v) {
        while (v >= 0x80) {
            m_bytes.push_back(static_cast<std::uint8_t>(v | 0x80));
            v >>= 7;
        }
        m_bytes.push_back(static_cast<std::uint8_t>(v));
    }
    void svarint(std::int64_t v) { varint(zigzag(v)); }
    void str(std::string_view s) {
        varint(s.size());
        m_bytes.insert(m_bytes.end(), s.begin(), s.end());
    }
    void raw(const void* data, std::size_t n) {
        const auto* p = static_cast<const std::uint8_t*>(data);
        m_bytes.insert(m_bytes.end(), p, p + n);
    }
    /// Overwrites a fixed-width value written earlier (for back-patched offsets).
    void patchU32(std::size_t at, std::uint32_t v) {
        for (int i = 0; i < 4; ++i) m_bytes[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
    }

private:
    template <typename T>
    void fixed(T v) {
        for (std::size_t i = 0; i < sizeof(T); ++i) m_bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    }
    std::vector<std::uint8_t> m_bytes;
};

/// Bounds-checked reader: any overrun sets failed() and returns zeros, so decoders can read a
/// whole record and check once. The first failure's description is kept.
class ByteReader {
public:
    explicit ByteReader(std::span<const std::uint8_t> data) : m_data(data) {}

    [[nodiscard]] bool failed() const { return m_failed; }
    [[nodiscard]] const std::string& error() const { return m_error; }
    [[nodiscard]] std::size_t position() const { return m_pos; }
    [[nodiscard]] std::size_t remaining() const { return m_data.size() - m_pos; }
    void fail(std::string what) {
        if (!m_failed) {
            m_failed = true;
            m_error = std::move(what) + " at byte " + std::to_string(m_pos);
        }
        m_pos = m_data.size();
    }

    std::uint8_t u8() { return fixed<std::uint8_t>(); }
    std::uint16_t u16() { return fixed<std::uint16_t>(); }
    std::uint32_t u32() { return fixed<std::uint32_t>(); }
    std::uint64_t u64() { return fixed<std::uint64_t>(); }
    std::int64_t i64() { return static_cast<std::int64_t>(fixed<std::uint64_t>()); }
    float f32() {
        const std::uint32_t u = fixed<std::uint32_t>();
        float v;
        std::memcpy(&v, &u, 4);
        return v;
    }
    double f64() {
        const std::uint64_t u = fixed<std::uint64_t>();
        double v;
        std::memcpy(&v, &u, 8);
        return v;
    }
    std::uint64_t varint() {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            if (m_pos >= m_data.size()) {
                fail("truncated varint");
                return 0;
            }
            const std::uint8_t b = m_data[m_pos++];
            v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
            if ((b & 0x80) == 0) return v;
        }
        fail("varint longer than 10 bytes");
        return 0;
    }
    std::int64_t svarint() { return unzigzag(varint()); }
    /// A count of elements that each take at least min_bytes; fails when it cannot fit.
    std::size_t count(std::size_t min_bytes, const char* what) {
        const std::uint64_t n = varint();
        if (failed()) return 0;
        if (min_bytes > 0 && n > remaining() / min_bytes) {
            fail(std::string("implausible ") + what + " count " + std::to_string(n));
            return 0;
        }
        return static_cast<std::size_t>(n);
    }
    std::string str() {
        const std::size_t n = count(1, "string length");
        if (failed()) return {};
        std::string s(reinterpret_cast<const char*>(m_data.data() + m_pos), n);
        m_pos += n;
        return s;
    }
    std::span<const std::uint8_t> bytes(std::size_t n) {
        if (n > remaining()) {
            fail("truncated block");
            return {};
        }
        auto s = m_data.subspan(m_pos, n);
        m_pos += n;
        return s;
    }

private:
    template <typename T>
    T fixed() {
        if (remaining() < sizeof(T)) {
            fail("truncated");
            return 0;
        }
        T v = 0;
        for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(m_data[m_pos + i]) << (8 * i));
        m_pos += sizeof(T);
        return v;
    }
    std::span<const std::uint8_t> m_data;
    std::size_t m_pos = 0;
    bool m_failed = false;
    std::string m_error;
};

}  // namespace navmap::map::detail
