// SPDX-License-Identifier: Apache-2.0
#include "toml_limits.h"

#include <vector>

namespace navmap::daemon {

namespace {

// One pass over the text with the little of TOML's grammar that says where keys, values and
// nesting are: comments, the four kinds of string, bare and quoted dotted keys, table headers,
// arrays and inline tables. Anything it does not understand is stepped over (toml++ reports it).
class TomlNestingScan {
public:
    TomlNestingScan(std::string_view text, std::string_view source, const TomlLimits& limits)
        : m_text(text), m_source(source), m_limits(limits) {}

    std::string run() {
        std::size_t table_depth = 0;  // parts of the latest [table] or [[array]] header
        while (!atEnd() && m_error.empty()) {
            if (m_open.empty()) {
                topLevel(table_depth);
            } else {
                inContainer();
            }
        }
        return m_error;
    }

private:
    struct Open {
        bool inline_table = false;  // else an array
        std::size_t depth = 0;      // of the values inside it
    };

    // A line outside any array or inline table: blank, comment, table header or key = value.
    void topLevel(std::size_t& table_depth) {
        skipBlanks();
        if (atEnd()) return;
        const char c = peek();
        if (c == '\n') {
            advance();
        } else if (c == '#') {
            skipToLineEnd();
        } else if (c == '[') {
            advance();
            if (peek() == '[') advance();
            skipBlanks();
            const std::size_t at = m_pos;
            const std::size_t parts = key();
            if (countValue(at) && withinDepth(parts, at, "table header")) table_depth = parts;
            skipToLineEnd();
        } else {
            keyValue(table_depth);
        }
    }

    // Inside an array (values) or an inline table (key = value pairs), over any number of lines.
    void inContainer() {
        skipBlanksAndNewlines();
        if (atEnd()) return;
        const char c = peek();
        if (c == ',') {
            advance();
        } else if (c == ']' || c == '}') {
            advance();
            m_open.pop_back();
        } else if (m_open.back().inline_table) {
            keyValue(m_open.back().depth);
        } else {
            const std::size_t at = m_pos;
            if (countValue(at)) value(m_open.back().depth, at);
        }
    }

    void keyValue(std::size_t depth) {
        const std::size_t at = m_pos;
        const std::size_t parts = key();
        if (parts == 0) {  // not a key: step over the character, toml++ will say what is wrong
            advance();
            return;
        }
        if (!countValue(at) || !withinDepth(depth + parts, at, "key")) return;
        skipBlanks();
        if (peek() != '=') return;
        advance();
        skipBlanks();
        value(depth + parts, m_pos);
    }

    // A value at `depth`: an array or inline table opens a level, a string or a bare word is
    // stepped over.
    void value(std::size_t depth, std::size_t at) {
        const char c = peek();
        if (c == '[' || c == '{') {
            if (!withinDepth(depth + 1, at, c == '[' ? "array" : "inline table")) return;
            m_open.push_back({c == '{', depth + 1});
            advance();
        } else if (c == '"' || c == '\'') {
            skipString();
        } else {
            while (!atEnd() && !endsBareValue(peek())) advance();
        }
    }

    // A dotted key; returns its number of parts (0: none here).
    std::size_t key() {
        std::size_t parts = 0;
        for (;;) {
            const char c = peek();
            if (c == '"' || c == '\'') {
                skipString();
            } else if (isBareKeyChar(c)) {
                while (!atEnd() && isBareKeyChar(peek())) advance();
            } else {
                break;
            }
            ++parts;
            skipBlanks();
            if (peek() != '.') break;
            advance();
            skipBlanks();
        }
        return parts;
    }

    // A basic or literal string, one-line or multi-line; an unterminated one-line string ends at
    // the end of its line.
    void skipString() {
        const char q = peek();
        const bool basic = q == '"';
        if (peek(1) == q && peek(2) == q) {
            advance(3);
            while (!atEnd()) {
                if (peek() == q && peek(1) == q && peek(2) == q) {
                    advance(3);
                    for (int extra = 0; extra < 2 && peek() == q; ++extra) advance();  // """a""""" ends in a"
                    return;
                }
                advance(basic && peek() == '\\' ? 2 : 1);
            }
            return;
        }
        advance();
        while (!atEnd() && peek() != '\n') {
            if (basic && peek() == '\\') {
                advance(peek(1) == '\n' ? 1 : 2);
                continue;
            }
            const char c = peek();
            advance();
            if (c == q) return;
        }
    }

    bool countValue(std::size_t at) {
        if (++m_values <= m_limits.max_values) return true;
        return fail(at, "more than " + std::to_string(m_limits.max_values) + " keys, tables and array elements");
    }

    bool withinDepth(std::size_t depth, std::size_t at, const char* what) {
        if (depth <= m_limits.max_depth) return true;
        return fail(at, std::string(what) + " nested more than " + std::to_string(m_limits.max_depth) +
                            " levels deep (tables, dotted keys, arrays and inline tables together)");
    }

    bool fail(std::size_t at, const std::string& what) {
        // The line and column of `at`, counted only now: the scan itself keeps no line table.
        std::size_t line = 1, column = 1;
        for (std::size_t i = 0; i < at && i < m_text.size(); ++i) {
            if (m_text[i] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        m_error = std::string(m_source) + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + what;
        return false;
    }

    static bool isBareKeyChar(char c) {
        const auto u = static_cast<unsigned char>(c);
        // Bytes of UTF-8 sequences count too: the scan must never see fewer parts than toml++.
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               u >= 0x80;
    }
    static bool endsBareValue(char c) {
        return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',' || c == ']' || c == '}' || c == '#';
    }

    [[nodiscard]] bool atEnd() const { return m_pos >= m_text.size(); }
    [[nodiscard]] char peek(std::size_t ahead = 0) const {
        return m_pos + ahead < m_text.size() ? m_text[m_pos + ahead] : '\0';
    }
    void advance(std::size_t n = 1) { m_pos = std::min(m_pos + n, m_text.size()); }
    void skipBlanks() {
        while (!atEnd() && (peek() == ' ' || peek() == '\t' || peek() == '\r')) advance();
    }
    void skipToLineEnd() {
        while (!atEnd() && peek() != '\n') advance();
    }
    void skipBlanksAndNewlines() {
        for (;;) {
            skipBlanks();
            if (peek() == '\n') {
                advance();
            } else if (peek() == '#') {
                skipToLineEnd();
            } else {
                return;
            }
        }
    }

    std::string_view m_text;
    std::string_view m_source;
    TomlLimits m_limits;
    std::size_t m_pos = 0;
    std::size_t m_values = 0;
    std::vector<Open> m_open;  // at most max_depth entries: deeper ones fail first
    std::string m_error;
};

}  // namespace

std::string checkTomlLimits(std::string_view text, std::string_view source_name, const TomlLimits& limits) {
    return TomlNestingScan(text, source_name, limits).run();
}

}  // namespace navmap::daemon
