// SPDX-License-Identifier: Apache-2.0
#pragma once
// Result<T>: a value or an error message, the expected-failure channel of ipc/
// (C++20 has no std::expected; this is the small subset the module needs).

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace navmap::ipc {

/// An expected failure: a human-readable message that names the input, the place and the problem.
struct Error {
    std::string message;
};

/// Either a T or an Error. Callers must test ok() before value().
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : m_v(std::in_place_index<0>, std::move(value)) {}      // NOLINT(implicit)
    Result(Error error) : m_v(std::in_place_index<1>, std::move(error)) {}  // NOLINT(implicit)

    bool ok() const noexcept { return m_v.index() == 0; }
    explicit operator bool() const noexcept { return ok(); }

    T& value() & {
        assert(ok());
        return std::get<0>(m_v);
    }
    const T& value() const& {
        assert(ok());
        return std::get<0>(m_v);
    }
    T&& value() && {
        assert(ok());
        return std::get<0>(std::move(m_v));
    }
    const Error& error() const {
        assert(!ok());
        return std::get<1>(m_v);
    }

private:
    std::variant<T, Error> m_v;
};

/// Result without a value.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : m_error(std::move(error.message)), m_failed(true) {}  // NOLINT(implicit)
    bool ok() const noexcept { return !m_failed; }
    explicit operator bool() const noexcept { return ok(); }
    const std::string& message() const noexcept { return m_error; }

private:
    std::string m_error;
    bool m_failed = false;
};

}  // namespace navmap::ipc
