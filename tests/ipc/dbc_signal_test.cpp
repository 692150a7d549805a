// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "navmap/ipc/can/dbc_signal.h"

using navmap::ipc::ByteOrder;
using navmap::ipc::DbcSignal;
using navmap::ipc::ValueType;

namespace {

DbcSignal makeSignal(unsigned start, unsigned length, ByteOrder order, bool is_signed = false, double factor = 1.0,
                     double offset = 0.0) {
    DbcSignal s;
    s.name = "S";
    s.start_bit = static_cast<std::uint16_t>(start);
    s.length = static_cast<std::uint16_t>(length);
    s.byte_order = order;
    s.is_signed = is_signed;
    s.factor = factor;
    s.offset = offset;
    return s;
}

}  // namespace

TEST(DbcSignal, IntelExtractsLittleEndianBits) {
    const std::array<std::uint8_t, 8> d{0x34, 0x12, 0xF0, 0x0F, 0, 0, 0, 0};
    EXPECT_EQ(makeSignal(0, 16, ByteOrder::Intel).extractBits(d), 0x1234U);
    EXPECT_EQ(makeSignal(4, 8, ByteOrder::Intel).extractBits(d), 0x23U);
    EXPECT_EQ(makeSignal(20, 8, ByteOrder::Intel).extractBits(d), 0xFFU);
    EXPECT_EQ(makeSignal(0, 1, ByteOrder::Intel).extractBits(d), 0U);
    EXPECT_EQ(makeSignal(2, 1, ByteOrder::Intel).extractBits(d), 1U);
}

TEST(DbcSignal, MotorolaExtractsSawtoothBits) {
    // Ford Veh_V_ActlBrk 7|16@0+: bytes 0 (MSB) and 1.
    const std::array<std::uint8_t, 8> d{0x12, 0x34, 0x56, 0, 0, 0, 0, 0};
    EXPECT_EQ(makeSignal(7, 16, ByteOrder::Motorola).extractBits(d), 0x1234U);
    // 23|16: bytes 2 and 3.
    EXPECT_EQ(makeSignal(23, 16, ByteOrder::Motorola).extractBits(d), 0x5600U);
    // 3|8: low nibble of byte 0 then high nibble of byte 1.
    EXPECT_EQ(makeSignal(3, 8, ByteOrder::Motorola).extractBits(d), 0x23U);
    // 6|15 (Ford steering): 7 bits of byte 0 and all of byte 1.
    EXPECT_EQ(makeSignal(6, 15, ByteOrder::Motorola).extractBits(d), 0x1234U);
    EXPECT_EQ(makeSignal(6, 15, ByteOrder::Motorola).bytesNeeded(), 2U);
    EXPECT_EQ(makeSignal(7, 16, ByteOrder::Motorola).bytesNeeded(), 2U);
    EXPECT_EQ(makeSignal(0, 1, ByteOrder::Motorola).bytesNeeded(), 1U);
    EXPECT_EQ(makeSignal(0, 2, ByteOrder::Motorola).bytesNeeded(), 2U);
    EXPECT_EQ(makeSignal(63, 64, ByteOrder::Intel).bytesNeeded(), 16U);
    EXPECT_EQ(makeSignal(7, 64, ByteOrder::Motorola).bytesNeeded(), 8U);
}

TEST(DbcSignal, SignedValuesAreSignExtended) {
    const std::array<std::uint8_t, 8> d{0xFE, 0xFF, 0x80, 0, 0, 0, 0, 0};
    EXPECT_DOUBLE_EQ(makeSignal(0, 16, ByteOrder::Intel, true).rawValue(d), -2.0);
    EXPECT_DOUBLE_EQ(makeSignal(0, 16, ByteOrder::Intel, false).rawValue(d), 65534.0);
    EXPECT_DOUBLE_EQ(makeSignal(16, 8, ByteOrder::Intel, true).rawValue(d), -128.0);
    EXPECT_DOUBLE_EQ(makeSignal(23, 8, ByteOrder::Motorola, true).rawValue(d), -128.0);
    const std::array<std::uint8_t, 8> all{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
    EXPECT_DOUBLE_EQ(makeSignal(0, 64, ByteOrder::Intel, true).rawValue(all), -1.0);
    EXPECT_DOUBLE_EQ(makeSignal(0, 64, ByteOrder::Intel, false).rawValue(all), 18446744073709551615.0);
}

TEST(DbcSignal, FactorOffsetAndShortPayload) {
    // Ford yaw rate 23|16 x0.0002 -6.5: raw 0x7EF4 = 32500 -> 0.0 rad/s.
    const std::array<std::uint8_t, 8> d{0x7e, 0xf4, 0x7e, 0xf4, 0x24, 0xf1, 0xf0, 0x00};
    const DbcSignal yaw = makeSignal(23, 16, ByteOrder::Motorola, false, 0.0002, -6.5);
    ASSERT_TRUE(yaw.decode(d).has_value());
    EXPECT_NEAR(*yaw.decode(d), 0.0, 1e-9);
    EXPECT_FALSE(yaw.decode(std::span(d.data(), 3)).has_value());
    EXPECT_TRUE(yaw.decode(std::span(d.data(), 4)).has_value());
}

TEST(DbcSignal, FloatValueTypes) {
    DbcSignal f = makeSignal(0, 32, ByteOrder::Intel);
    f.value_type = ValueType::Float32;
    std::array<std::uint8_t, 8> d{};
    ASSERT_TRUE(f.encode(d, 1.5).ok());
    EXPECT_EQ(d[3], 0x3F);  // 1.5f = 0x3FC00000, little endian
    EXPECT_EQ(d[2], 0xC0);
    EXPECT_DOUBLE_EQ(*f.decode(d), 1.5);
    DbcSignal g = makeSignal(0, 64, ByteOrder::Intel);
    g.value_type = ValueType::Float64;
    ASSERT_TRUE(g.encode(d, -1234.5678).ok());
    EXPECT_DOUBLE_EQ(*g.decode(d), -1234.5678);
}

TEST(DbcSignal, EncodeRejectsValuesThatDoNotFit) {
    std::array<std::uint8_t, 8> d{};
    const DbcSignal u8 = makeSignal(0, 8, ByteOrder::Intel);
    EXPECT_TRUE(u8.encode(d, 255).ok());
    const auto over = u8.encode(d, 256);
    ASSERT_FALSE(over.ok());
    EXPECT_NE(over.message().find("does not fit 8 unsigned bits"), std::string::npos) << over.message();
    EXPECT_FALSE(u8.encode(d, -1).ok());
    EXPECT_FALSE(u8.encode(d, std::nan("")).ok());
    const DbcSignal s8 = makeSignal(0, 8, ByteOrder::Intel, true);
    EXPECT_TRUE(s8.encode(d, -128).ok());
    EXPECT_FALSE(s8.encode(d, 128).ok());
    const DbcSignal u64 = makeSignal(0, 64, ByteOrder::Intel);
    EXPECT_FALSE(u64.encode(d, 18446744073709551616.0).ok());
    const DbcSignal far = makeSignal(60, 8, ByteOrder::Intel);
    EXPECT_FALSE(far.encode(d, 1).ok());  // needs 9 bytes
}

TEST(DbcSignal, EncodeLeavesOtherBitsAlone) {
    std::array<std::uint8_t, 8> d{};
    d.fill(0xAA);
    const DbcSignal m = makeSignal(3, 8, ByteOrder::Motorola);
    ASSERT_TRUE(m.encode(d, 0x00).ok());
    EXPECT_EQ(d[0], 0xA0);
    EXPECT_EQ(d[1], 0x0A);
    EXPECT_EQ(d[2], 0xAA);
}

// Property: for random layouts in both byte orders, encode(decode(x)) round-trips and touches only
// the signal's own bits.
TEST(DbcSignal, RandomRoundTripBothByteOrders) {
    std::mt19937_64 rng(1234);
    for (int iter = 0; iter < 20000; ++iter) {
        const bool intel = (rng() & 1U) != 0;
        const unsigned length = 1 + static_cast<unsigned>(rng() % 64);
        DbcSignal s = makeSignal(0, length, intel ? ByteOrder::Intel : ByteOrder::Motorola, (rng() & 1U) != 0);
        // Pick a start bit whose bits fit 64 bytes.
        do {
            s.start_bit = static_cast<std::uint16_t>(rng() % 512);
        } while (s.bytesNeeded() > 64);
        std::array<std::uint8_t, 64> before{};
        for (auto& b : before) {
            b = static_cast<std::uint8_t>(rng());
        }
        std::array<std::uint8_t, 64> data = before;
        const std::uint64_t bits = rng() & (length == 64 ? ~0ULL : ((1ULL << length) - 1));
        s.insertBits(data, bits);
        ASSERT_EQ(s.extractBits(data), bits) << "start " << s.start_bit << " len " << length << " intel " << intel;
        // Clearing the signal and comparing with the original outside it: only own bits changed.
        std::array<std::uint8_t, 64> a = before;
        std::array<std::uint8_t, 64> b = data;
        s.insertBits(a, 0);
        s.insertBits(b, 0);
        ASSERT_EQ(a, b);
        // Number of set bits of the signal equals popcount(bits).
        std::array<std::uint8_t, 64> zero{};
        s.insertBits(zero, bits);
        int ones = 0;
        for (auto z : zero) {
            ones += std::popcount(static_cast<unsigned>(z));
        }
        ASSERT_EQ(ones, std::popcount(bits));
    }
}
