// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/candump_reader.h"

#include <array>
#include <charconv>
#include <cstdio>
#include <fstream>

namespace navmap::ipc {
namespace {

int hexValue(char c) noexcept {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

bool isBlank(char c) noexcept { return c == ' ' || c == '\t'; }

/// Printable excerpt of untrusted text for error messages.
std::string excerpt(std::string_view s) {
    std::string out;
    for (const char c : s.substr(0, 32)) {
        const auto u = static_cast<unsigned char>(c);
        out.push_back(u >= 0x20 && u < 0x7F ? c : '?');
    }
    if (s.size() > 32) {
        out += "...";
    }
    return out;
}

constexpr std::uint32_t kErrFlag = 0x20000000U;  // CAN_ERR_FLAG in candump's 8-digit ids

Result<CanFrame> parseFrameToken(std::string_view tok) {
    CanFrame f;
    const std::size_t hash = tok.find('#');
    if (hash == std::string_view::npos) {
        return Error{"frame '" + excerpt(tok) + "' has no '#'"};
    }
    const std::string_view id_text = tok.substr(0, hash);
    if (id_text.size() != 3 && id_text.size() != 8) {
        return Error{"CAN id '" + excerpt(id_text) + "' must have 3 (11-bit) or 8 (29-bit) hex digits"};
    }
    std::uint32_t id = 0;
    for (const char c : id_text) {
        const int v = hexValue(c);
        if (v < 0) {
            return Error{"CAN id '" + excerpt(id_text) + "' is not hex"};
        }
        id = (id << 4U) | static_cast<std::uint32_t>(v);
    }
    if (id_text.size() == 3) {
        if (id > kCanMaxStandardId) {
            return Error{"11-bit CAN id 0x" + std::string(id_text) + " is out of range (max 0x7FF)"};
        }
    } else if ((id & kErrFlag) != 0) {
        f.flags |= kCanError;
        id &= kCanMaxExtendedId;
    } else if (id > kCanMaxExtendedId) {
        return Error{"29-bit CAN id 0x" + std::string(id_text) + " is out of range (max 0x1FFFFFFF)"};
    } else {
        f.flags |= kCanExtended;
    }
    f.id = id;

    std::string_view rest = tok.substr(hash + 1);
    bool fd = false;
    if (!rest.empty() && rest[0] == '#') {
        fd = true;
        if (f.error()) {
            return Error{"error frames cannot be CAN FD frames"};
        }
        if (rest.size() < 2) {
            return Error{"CAN FD frame without the flags nibble after '##'"};
        }
        if (rest[1] == '#') {
            return Error{"CAN XL frames ('###') are not supported"};
        }
        const int fl = hexValue(rest[1]);
        if (fl < 0) {
            return Error{"CAN FD flags '" + excerpt(rest.substr(1, 1)) + "' are not hex"};
        }
        f.flags |= kCanFd;
        if ((fl & 1) != 0) {
            f.flags |= kCanBrs;
        }
        if ((fl & 2) != 0) {
            f.flags |= kCanEsi;
        }
        rest.remove_prefix(2);
    } else if (!rest.empty() && (rest[0] == 'R' || rest[0] == 'r')) {
        if (f.error()) {
            return Error{"error frames cannot be remote frames"};
        }
        f.flags |= kCanRtr;
        rest.remove_prefix(1);
        if (!rest.empty() && rest[0] != '_') {
            const int len = hexValue(rest[0]);
            if (len < 0 || len > 8) {
                return Error{"remote frame length '" + excerpt(rest.substr(0, 1)) + "' is not 0..8"};
            }
            f.len = static_cast<std::uint8_t>(len);
            rest.remove_prefix(1);
        }
        if (!rest.empty() && rest[0] == '_') {
            if (rest.size() != 2 || f.len != 8 || hexValue(rest[1]) < 9) {
                return Error{"bad len8_dlc suffix '" + excerpt(rest) + "'"};
            }
            rest.remove_prefix(2);
        }
        if (!rest.empty()) {
            return Error{"unexpected text '" + excerpt(rest) + "' after a remote frame"};
        }
        return f;
    }

    const unsigned max_len = fd ? kCanMaxFdLen : kCanMaxClassicLen;
    unsigned len = 0;
    std::size_t i = 0;
    while (i < rest.size()) {
        if (rest[i] == '.') {
            ++i;
            continue;
        }
        if (rest[i] == '_' && !fd) {
            break;
        }
        if (i + 1 >= rest.size() || rest[i + 1] == '.' || rest[i + 1] == '_') {
            return Error{"odd number of hex digits in data '" + excerpt(rest) + "'"};
        }
        const int hi = hexValue(rest[i]);
        const int lo = hexValue(rest[i + 1]);
        if (hi < 0 || lo < 0) {
            return Error{"data '" + excerpt(rest) + "' is not hex"};
        }
        if (len >= max_len) {
            return Error{std::string(fd ? "CAN FD" : "classic CAN") + " frame has more than " +
                         std::to_string(max_len) + " data bytes"};
        }
        f.data[len++] = static_cast<std::uint8_t>((hi << 4) | lo);
        i += 2;
    }
    if (i < rest.size()) {  // "_<dlc>": len8_dlc for classic frames with 8 bytes and DLC 9..15
        const std::string_view suffix = rest.substr(i);
        if (suffix.size() != 2 || len != 8 || hexValue(suffix[1]) < 9) {
            return Error{"bad len8_dlc suffix '" + excerpt(suffix) + "'"};
        }
    }
    if (fd && !isValidFdLength(len)) {
        return Error{"CAN FD frame has " + std::to_string(len) + " data bytes, not a valid FD length"};
    }
    if (f.error() && len != 8) {
        return Error{"error frame must have 8 data bytes, has " + std::to_string(len)};
    }
    f.len = static_cast<std::uint8_t>(len);
    return f;
}

}  // namespace

CandumpReader::CandumpReader(std::string source_name) : m_source_name(std::move(source_name)) {}

Result<CandumpReader::Parsed> CandumpReader::parseLine(std::string_view line) {
    while (!line.empty() && (isBlank(line.back()) || line.back() == '\r')) {
        line.remove_suffix(1);
    }
    if (line.size() > kMaxLineLength) {
        return Error{"line is longer than " + std::to_string(kMaxLineLength) + " characters"};
    }
    std::size_t p = 0;
    while (p < line.size() && isBlank(line[p])) {
        ++p;
    }
    if (p >= line.size() || line[p] != '(') {
        return Error{"expected '(' and a timestamp at the start, got '" + excerpt(line.substr(p)) + "'"};
    }
    ++p;
    std::uint64_t sec = 0;
    {
        const auto [ptr, ec] = std::from_chars(line.data() + p, line.data() + line.size(), sec);
        if (ec == std::errc::result_out_of_range ||
            (ec == std::errc{} && ptr != line.data() + p && sec > kMaxTimestampSeconds)) {
            // CanTime counts nanoseconds in an int64: later seconds would overflow it.
            return Error{"timestamp " + excerpt(line.substr(p, static_cast<std::size_t>(ptr - line.data()) - p)) +
                         " s is out of range (0 to " + std::to_string(kMaxTimestampSeconds) + " s)"};
        }
        if (ec != std::errc{} || ptr == line.data() + p) {
            return Error{"bad timestamp seconds in '" + excerpt(line) + "'"};
        }
        p = static_cast<std::size_t>(ptr - line.data());
    }
    std::uint64_t nanos = 0;
    if (p < line.size() && line[p] == '.') {
        ++p;
        unsigned digits = 0;
        while (p < line.size() && line[p] >= '0' && line[p] <= '9') {
            if (digits < 9) {
                nanos = nanos * 10U + static_cast<unsigned>(line[p] - '0');
            }
            ++digits;
            ++p;
        }
        if (digits == 0) {
            return Error{"timestamp has no digits after '.'"};
        }
        for (unsigned d = digits; d < 9; ++d) {
            nanos *= 10U;
        }
    }
    if (p >= line.size() || line[p] != ')') {
        return Error{"timestamp is not closed by ')' in '" + excerpt(line) + "'"};
    }
    ++p;
    if (p >= line.size() || !isBlank(line[p])) {
        return Error{"expected a blank and an interface name after the timestamp"};
    }
    while (p < line.size() && isBlank(line[p])) {
        ++p;
    }
    const std::size_t if_start = p;
    while (p < line.size() && !isBlank(line[p])) {
        const auto u = static_cast<unsigned char>(line[p]);
        if (u < 0x21 || u > 0x7E) {
            return Error{"interface name contains a non-printable byte"};
        }
        ++p;
    }
    const std::string_view iface = line.substr(if_start, p - if_start);
    if (iface.empty() || iface.size() > 15) {
        return Error{"interface name '" + excerpt(iface) + "' must have 1..15 characters"};
    }
    while (p < line.size() && isBlank(line[p])) {
        ++p;
    }
    const std::size_t fr_start = p;
    while (p < line.size() && !isBlank(line[p])) {
        ++p;
    }
    const std::string_view frame_text = line.substr(fr_start, p - fr_start);
    if (frame_text.empty()) {
        return Error{"line is truncated: no frame after the interface name"};
    }
    while (p < line.size() && isBlank(line[p])) {
        ++p;
    }
    const std::string_view trailer = line.substr(p);
    if (!trailer.empty() && trailer != "R" && trailer != "T") {
        return Error{"unexpected text '" + excerpt(trailer) + "' after the frame"};
    }
    auto frame = parseFrameToken(frame_text);
    if (!frame) {
        return frame.error();
    }
    Parsed out{std::move(frame).value(), iface};
    out.frame.timestamp = CanTime(std::chrono::seconds(sec) + std::chrono::nanoseconds(nanos));
    return out;
}

void CandumpReader::reject(const std::string& message) {
    ++m_counters.malformed;
    if (m_errors.size() < kMaxErrors) {
        m_errors.push_back({m_line, m_source_name + ":" + std::to_string(m_line) + ": " + message});
    }
}

bool CandumpReader::feedLine(std::string_view line, CandumpRecord& out) {
    ++m_counters.lines;
    ++m_line;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || line[first] == '#' || line[first] == ';') {
        ++m_counters.skipped;
        return false;
    }
    auto parsed = parseLine(line);
    if (!parsed) {
        reject(parsed.error().message);
        return false;
    }
    const Parsed& p = parsed.value();
    std::size_t index = 0;
    for (; index < m_interfaces.size(); ++index) {
        if (m_interfaces[index] == p.interface_name) {
            break;
        }
    }
    if (index == m_interfaces.size()) {
        if (m_interfaces.size() >= 0xFFFF) {
            ++m_counters.malformed;
            return false;
        }
        m_interfaces.emplace_back(p.interface_name);
    }
    out.frame = p.frame;
    out.interface_index = index;
    ++m_counters.frames;
    if (p.frame.fd()) {
        ++m_counters.fd_frames;
    }
    if (p.frame.rtr()) {
        ++m_counters.remote_frames;
    }
    if (p.frame.error()) {
        ++m_counters.error_frames;
    }
    return true;
}

Status CandumpReader::feedBytes(std::string_view bytes, const RecordSink& sink) {
    if (!m_failure.empty()) {
        return Error{m_failure};
    }
    CandumpRecord rec;
    for (const char c : bytes) {
        const auto u = static_cast<unsigned char>(c);
        if ((u < 0x20 && c != '\t' && c != '\r' && c != '\n') || u == 0x7F) {
            // Text logs have no control bytes: this is a binary file (or /dev/zero). Reading on
            // would take forever on a device and turn garbage into thousands of "lines".
            char what[160];
            std::snprintf(what, sizeof what, ": byte 0x%02X at offset %llu (line %zu): binary data, not a candump log",
                          u, static_cast<unsigned long long>(m_offset), m_line + 1);
            m_failure = m_source_name + what;
            return Error{m_failure};
        }
        ++m_offset;
        if (c == '\n') {
            if (m_skipping) {
                ++m_counters.lines;
                ++m_line;
                reject("line is longer than " + std::to_string(kMaxLineLength) + " characters");
                m_skipping = false;
                m_skipped = 0;
            } else if (feedLine(m_partial, rec)) {
                sink(rec);
            }
            m_partial.clear();
            continue;
        }
        if (m_skipping) {
            if (++m_skipped > kMaxSkipBytes) {
                m_failure = m_source_name + ":" + std::to_string(m_line + 1) + ": no end of line in " +
                            std::to_string(kMaxSkipBytes) + " bytes, not a candump log";
                return Error{m_failure};
            }
            continue;
        }
        m_partial.push_back(c);
        if (m_partial.size() > kMaxLineLength + 1) {  // one more than parseLine takes: it says "longer than"
            m_skipping = true;
            m_skipped = m_partial.size();
            m_partial.clear();
            m_partial.shrink_to_fit();
        }
    }
    return {};
}

void CandumpReader::finishBytes(const RecordSink& sink) {
    if (!m_failure.empty()) {
        return;
    }
    CandumpRecord rec;
    if (m_skipping) {
        ++m_counters.lines;
        ++m_line;
        reject("line is longer than " + std::to_string(kMaxLineLength) + " characters");
    } else if (!m_partial.empty() && feedLine(m_partial, rec)) {
        sink(rec);
    }
    m_partial.clear();
    m_skipping = false;
    m_skipped = 0;
}

void CandumpReader::restartInput() {
    m_partial.clear();
    m_skipping = false;
    m_skipped = 0;
    m_line = 0;
    m_offset = 0;
    m_failure.clear();
}

std::vector<CandumpRecord> CandumpReader::readAll(std::istream& in) {
    std::vector<CandumpRecord> out;
    const RecordSink sink = [&](const CandumpRecord& r) { out.push_back(r); };
    std::array<char, 16 * 1024> buf;
    while (in) {
        in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
        const auto n = in.gcount();
        if (n <= 0) {
            break;
        }
        if (!feedBytes(std::string_view(buf.data(), static_cast<std::size_t>(n)), sink).ok()) {
            return out;
        }
    }
    finishBytes(sink);
    return out;
}

std::vector<CanFrame> CandumpLog::frames(std::string_view interface_name) const {
    std::vector<CanFrame> out;
    out.reserve(records.size());
    for (const auto& r : records) {
        if (interface_name.empty() || interfaces[r.interface_index] == interface_name) {
            out.push_back(r.frame);
        }
    }
    return out;
}

Result<CandumpLog> loadCandumpFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return Error{"open(" + path.string() + "): cannot read candump file"};
    }
    CandumpReader reader(path.string());
    CandumpLog log;
    log.records = reader.readAll(in);
    if (in.bad()) {
        return Error{"read(" + path.string() + "): I/O error"};
    }
    if (!reader.failure().empty()) {
        return Error{reader.failure()};
    }
    log.interfaces = reader.interfaces();
    log.counters = reader.counters();
    log.errors = reader.errors();
    return log;
}

}  // namespace navmap::ipc
