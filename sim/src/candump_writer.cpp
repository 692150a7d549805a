// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/candump_writer.h"

#include <cerrno>
#include <cinttypes>
#include <cstring>
#include <system_error>
#include <utility>

namespace navmap::sim {

std::string formatCandumpLine(const ipc::CanFrame& frame, std::string_view iface) {
    const auto us = std::chrono::duration_cast<std::chrono::microseconds>(frame.timestamp.time_since_epoch()).count();
    std::int64_t sec = us / 1000000;
    std::int64_t frac = us % 1000000;
    if (frac < 0) {  // before 1970: keep the fraction positive as candump would print it
        frac += 1000000;
        --sec;
    }
    char stamp[48];
    std::snprintf(stamp, sizeof stamp, "(%" PRId64 ".%06" PRId64 ") ", sec, frac);
    std::string line(stamp);
    line.append(iface);
    line.push_back(' ');
    line += ipc::formatCandumpPayload(frame);
    return line;
}

ipc::Result<CandumpWriter> CandumpWriter::open(const std::filesystem::path& path, std::string iface) {
    if (iface.empty() || iface.find_first_of(" \t\n()#") != std::string::npos) {
        return ipc::Error{"interface name '" + iface + "' is not usable in a candump log"};
    }
    CandumpWriter w;
    w.m_path = path;
    w.m_tmp = path;
    w.m_tmp += ".tmp";
    w.m_iface = std::move(iface);
    w.m_file = std::fopen(w.m_tmp.c_str(), "w");
    if (w.m_file == nullptr) {
        return ipc::Error{"fopen(" + w.m_tmp.string() + "): " + std::strerror(errno)};
    }
    return w;
}

CandumpWriter::CandumpWriter(CandumpWriter&& other) noexcept
    : m_file(std::exchange(other.m_file, nullptr)),
      m_path(std::move(other.m_path)),
      m_tmp(std::move(other.m_tmp)),
      m_iface(std::move(other.m_iface)),
      m_lines(other.m_lines) {}

CandumpWriter& CandumpWriter::operator=(CandumpWriter&& other) noexcept {
    if (this != &other) {
        discard();
        m_file = std::exchange(other.m_file, nullptr);
        m_path = std::move(other.m_path);
        m_tmp = std::move(other.m_tmp);
        m_iface = std::move(other.m_iface);
        m_lines = other.m_lines;
    }
    return *this;
}

CandumpWriter::~CandumpWriter() { discard(); }

void CandumpWriter::discard() noexcept {
    if (m_file != nullptr) {
        std::fclose(m_file);
        m_file = nullptr;
        std::error_code ec;
        std::filesystem::remove(m_tmp, ec);  // never throws; an unpublished log is just garbage
    }
}

ipc::Status CandumpWriter::write(const ipc::CanFrame& frame) {
    if (m_file == nullptr) return ipc::Error{"write(" + m_path.string() + "): log is closed"};
    std::string line = formatCandumpLine(frame, m_iface);
    line.push_back('\n');
    if (std::fwrite(line.data(), 1, line.size(), m_file) != line.size()) {
        return ipc::Error{"fwrite(" + m_tmp.string() + "): " + std::strerror(errno)};
    }
    ++m_lines;
    return {};
}

ipc::Status CandumpWriter::close() {
    if (m_file == nullptr) return ipc::Error{"close(" + m_path.string() + "): log is not open"};
    const bool flushed = std::fflush(m_file) == 0 && std::ferror(m_file) == 0;
    const int flush_errno = errno;
    const bool closed = std::fclose(m_file) == 0;
    m_file = nullptr;
    if (!flushed || !closed) {
        std::error_code ec;
        std::filesystem::remove(m_tmp, ec);
        return ipc::Error{"fclose(" + m_tmp.string() + "): " + std::strerror(flushed ? errno : flush_errno)};
    }
    std::error_code ec;
    std::filesystem::rename(m_tmp, m_path, ec);
    if (ec) {
        std::filesystem::remove(m_tmp, ec);
        return ipc::Error{"rename(" + m_tmp.string() + ", " + m_path.string() + "): " + ec.message()};
    }
    return {};
}

}  // namespace navmap::sim
