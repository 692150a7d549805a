// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/dbc_database.h"

#include <cctype>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>

#include "navmap/common/untrusted_file.h"

namespace navmap::ipc {
namespace {

// Real DBC files reach a few MiB (a whole vehicle's buses); 32 MiB bounds what a wrong file costs.
constexpr FileKind kDbcFile{"DBC file", std::uint64_t{32} << 20};

/// The one DBC number reader (std::from_chars): the T that `text` starts with and how many
/// characters it took; nothing when `text` does not start with one or it does not fit T.
template <class T>
std::optional<std::pair<T, std::size_t>> parseNumberPrefix(std::string_view text) {
    T v{};
    const char* first = text.data();
    const auto [ptr, ec] = std::from_chars(first, first + text.size(), v);
    if (ec != std::errc{} || ptr == first) {
        return std::nullopt;
    }
    return std::pair<T, std::size_t>(v, static_cast<std::size_t>(ptr - first));
}

/// Cursor over one DBC statement (one line, or several when a quoted string spans lines).
class Lexer {
public:
    explicit Lexer(std::string_view text) : m_text(text) {}

    void skipWs() {
        while (m_pos < m_text.size() && std::isspace(static_cast<unsigned char>(m_text[m_pos])) != 0) {
            ++m_pos;
        }
    }
    bool atEnd() {
        skipWs();
        return m_pos >= m_text.size();
    }
    char peek() {
        skipWs();
        return m_pos < m_text.size() ? m_text[m_pos] : '\0';
    }
    bool accept(char c) {
        if (peek() == c) {
            ++m_pos;
            return true;
        }
        return false;
    }
    std::optional<std::string_view> ident() {
        skipWs();
        const std::size_t start = m_pos;
        while (m_pos < m_text.size()) {
            const auto c = static_cast<unsigned char>(m_text[m_pos]);
            if (std::isalnum(c) == 0 && c != '_') {
                break;
            }
            ++m_pos;
        }
        if (m_pos == start) {
            return std::nullopt;
        }
        return m_text.substr(start, m_pos - start);
    }
    std::optional<std::uint64_t> unsignedInt() {
        skipWs();
        return numberOf<std::uint64_t>();
    }
    std::optional<std::int64_t> signedInt() {
        skipWs();
        return numberOf<std::int64_t>();
    }
    std::optional<double> number() {
        skipWs();
        if (m_pos < m_text.size() && m_text[m_pos] == '+') {
            ++m_pos;  // from_chars does not take a leading '+'
        }
        return numberOf<double>();
    }
    std::optional<std::string> quoted() {
        if (!accept('"')) {
            return std::nullopt;
        }
        std::string out;
        while (m_pos < m_text.size()) {
            const char c = m_text[m_pos++];
            if (c == '\\' && m_pos < m_text.size()) {
                out.push_back(m_text[m_pos++]);
            } else if (c == '"') {
                return out;
            } else {
                out.push_back(c);
            }
        }
        return std::nullopt;  // unterminated
    }
    /// Rest of the statement (for receivers lists).
    std::string_view rest() {
        skipWs();
        return m_text.substr(m_pos);
    }

private:
    /// The number of type T right at the cursor; the cursor moves past it.
    template <class T>
    std::optional<T> numberOf() {
        const auto v = parseNumberPrefix<T>(m_text.substr(m_pos));
        if (v) {
            m_pos += v->second;
        }
        return v ? std::optional<T>(v->first) : std::nullopt;
    }

    std::string_view m_text;
    std::size_t m_pos = 0;
};

/// Whether a statement is inside a quoted string (unescaped '"' seen an odd number of times), fed
/// piece by piece: a statement whose string spans many lines is scanned once, not once per line
/// (re-scanning made a stray '"' early in an 800 kB DBC take minutes).
class QuoteState {
public:
    void feed(std::string_view s) {
        for (const char c : s) {
            if (m_escaped) {
                m_escaped = false;
            } else if (c == '\\' && m_in_string) {
                m_escaped = true;
            } else if (c == '"') {
                m_in_string = !m_in_string;
            }
        }
    }
    bool inString() const { return m_in_string; }

private:
    bool m_in_string = false;
    bool m_escaped = false;  // a backslash inside a string: the next character is taken as is
};

}  // namespace

/// The DBC parser proper: statement by statement, keeping the current BO_ for SG_ lines.
class DbcParser {
public:
    DbcParser(DbcDatabase& db, DbcDatabase::Mode mode) : m_db(db), m_mode(mode) {}

    /// Returns false when parsing must stop (strict mode error).
    bool statement(std::string_view text, std::size_t line, bool indented) {
        Lexer lex(text);
        const auto keyword = lex.ident();
        if (!keyword) {
            // Lines that do not start with an identifier are not DBC statements we know.
            return fail(line, "unexpected text '" + shorten(text) + "'");
        }
        if (m_in_ns_block && indented) {
            return true;  // the symbol list after NS_
        }
        m_in_ns_block = false;
        if (*keyword == "NS_") {
            m_in_ns_block = true;
            return true;
        }
        if (*keyword == "BO_") {
            return message(lex, line);
        }
        if (*keyword == "SG_") {
            return signal(lex, line);
        }
        if (*keyword == "VAL_") {
            return valueNames(lex, line);
        }
        if (*keyword == "SIG_VALTYPE_") {
            return valueType(lex, line);
        }
        // Everything else (VERSION, BS_, BU_, CM_, BA_DEF_, BA_, VAL_TABLE_, BO_TX_BU_, EV_, SG_MUL_VAL_,
        // SIG_GROUP_, ...) is skipped. A statement ends a message's signal list.
        m_current = -1;
        return true;
    }

    bool finish() {
        for (auto& msg : m_db.m_messages) {
            for (const auto& s : msg.signals) {
                if (s.mux_role == MuxRole::Multiplexed && msg.multiplexor < 0) {
                    if (!fail(s.line, "SG_ " + s.name + ": multiplexed signal in message " + msg.name +
                                          " which has no multiplexor (M) signal")) {
                        return false;
                    }
                }
            }
        }
        return true;
    }

    bool fail(std::size_t line, std::string what) {
        ++m_db.m_diagnostic_count;
        DbcDiagnostic d{line, m_db.m_source_name + ":" + std::to_string(line) + ": " + std::move(what)};
        if (m_mode == DbcDatabase::Mode::Strict) {
            m_first_error = d.message;
            return false;
        }
        if (m_db.m_diagnostics.size() < DbcDatabase::kMaxDiagnostics) {
            m_db.m_diagnostics.push_back(std::move(d));
        }
        return true;
    }

    const std::string& firstError() const { return m_first_error; }

private:
    static std::string shorten(std::string_view s) {
        std::string out(s.substr(0, 40));
        for (char& c : out) {
            if (std::isprint(static_cast<unsigned char>(c)) == 0) {
                c = '?';
            }
        }
        return s.size() > 40 ? out + "..." : out;
    }

    bool message(Lexer& lex, std::size_t line) {
        m_current = -1;
        const auto raw_id = lex.unsignedInt();
        if (!raw_id) {
            return fail(line, "BO_: expected a numeric message id");
        }
        const auto name = lex.ident();
        if (!name) {
            return fail(line, "BO_ " + std::to_string(*raw_id) + ": expected a message name");
        }
        if (!lex.accept(':')) {
            return fail(line, "BO_ " + std::string(*name) + ": expected ':' after the name");
        }
        const auto size = lex.unsignedInt();
        if (!size || *size > kCanMaxFdLen) {
            return fail(line, "BO_ " + std::string(*name) + ": size must be 0..64 bytes");
        }
        if (*name == "VECTOR__INDEPENDENT_SIG_MSG") {
            m_current = -2;  // pseudo message of unassigned signals: skip its SG_ lines
            return true;
        }
        DbcMessage msg;
        msg.name = std::string(*name);
        msg.size = static_cast<std::uint8_t>(*size);
        msg.line = line;
        if ((*raw_id & 0x80000000U) != 0) {
            msg.extended = true;
            msg.id = static_cast<std::uint32_t>(*raw_id & 0x7FFFFFFFU);
        } else {
            msg.id = static_cast<std::uint32_t>(*raw_id);
            msg.extended = *raw_id > kCanMaxStandardId;  // cannot be an 11-bit id
        }
        if (*raw_id > 0xFFFFFFFFULL || msg.id > kCanMaxExtendedId) {
            return fail(line, "BO_ " + msg.name + ": id " + std::to_string(*raw_id) + " is not a CAN id");
        }
        if (const auto tx = lex.ident()) {
            msg.transmitter = std::string(*tx);
        }
        if (m_db.m_by_key.count(msg.key()) != 0) {
            return fail(line, "BO_ " + msg.name + ": duplicate message id " + std::to_string(msg.id));
        }
        if (m_db.m_by_name.count(msg.name) != 0) {
            return fail(line, "BO_ " + msg.name + ": duplicate message name");
        }
        m_db.m_by_key.emplace(msg.key(), m_db.m_messages.size());
        m_db.m_by_name.emplace(msg.name, m_db.m_messages.size());
        m_current = static_cast<int>(m_db.m_messages.size());
        m_db.m_messages.push_back(std::move(msg));
        return true;
    }

    bool signal(Lexer& lex, std::size_t line) {
        if (m_current == -2) {
            return true;
        }
        const auto name = lex.ident();
        if (!name) {
            return fail(line, "SG_: expected a signal name");
        }
        const std::string sg = "SG_ " + std::string(*name);
        if (m_current < 0) {
            return fail(line, sg + ": signal outside a BO_ message");
        }
        DbcMessage& msg = m_db.m_messages[static_cast<std::size_t>(m_current)];
        DbcSignal s;
        s.name = std::string(*name);
        s.line = line;
        if (lex.peek() != ':') {
            const auto mux = lex.ident();
            if (!mux) {
                return fail(line, sg + ": expected ':' or a multiplexer indicator");
            }
            if (*mux == "M") {
                s.mux_role = MuxRole::Multiplexor;
            } else if (mux->size() >= 2 && (*mux)[0] == 'm') {
                std::string_view digits = mux->substr(1);
                if (digits.back() == 'M') {
                    s.also_multiplexor = true;
                    digits.remove_suffix(1);
                }
                const auto v = parseNumberPrefix<std::uint32_t>(digits);
                if (!v || v->second != digits.size()) {
                    return fail(line, sg + ": bad multiplexer indicator '" + std::string(*mux) + "'");
                }
                s.mux_role = MuxRole::Multiplexed;
                s.mux_value = v->first;
            } else {
                return fail(line, sg + ": bad multiplexer indicator '" + std::string(*mux) + "'");
            }
        }
        if (!lex.accept(':')) {
            return fail(line, sg + ": expected ':'");
        }
        const auto start = lex.unsignedInt();
        if (!start || !lex.accept('|')) {
            return fail(line, sg + ": expected <start bit>|<length>");
        }
        const auto length = lex.unsignedInt();
        if (!length || !lex.accept('@')) {
            return fail(line, sg + ": expected <length>@<byte order>");
        }
        if (*length < 1 || *length > 64) {
            return fail(line, sg + ": length " + std::to_string(*length) + " is not 1..64 bits");
        }
        if (*start >= 512) {
            return fail(line, sg + ": start bit " + std::to_string(*start) + " is beyond 64 bytes");
        }
        s.start_bit = static_cast<std::uint16_t>(*start);
        s.length = static_cast<std::uint16_t>(*length);
        if (lex.accept('0')) {
            s.byte_order = ByteOrder::Motorola;
        } else if (lex.accept('1')) {
            s.byte_order = ByteOrder::Intel;
        } else {
            return fail(line, sg + ": byte order must be @0 (Motorola) or @1 (Intel)");
        }
        if (lex.accept('-')) {
            s.is_signed = true;
        } else if (!lex.accept('+')) {
            return fail(line, sg + ": expected + (unsigned) or - (signed)");
        }
        // (factor,offset) [min|max]: each number with the punctuation around it.
        const struct {
            char open;  // 0: none
            double* value;
            char close;
            const char* missing_open;
            const char* bad_value;
        } numbers[] = {
            {'(', &s.factor, ',', "expected (factor,offset)", "bad factor in (factor,offset)"},
            {0, &s.offset, ')', nullptr, "bad offset in (factor,offset)"},
            {'[', &s.minimum, '|', "expected [min|max]", "bad minimum in [min|max]"},
            {0, &s.maximum, ']', nullptr, "bad maximum in [min|max]"},
        };
        for (const auto& n : numbers) {
            if (n.open != 0 && !lex.accept(n.open)) {
                return fail(line, sg + ": " + n.missing_open);
            }
            const auto v = lex.number();
            if (!v || !lex.accept(n.close)) {
                return fail(line, sg + ": " + n.bad_value);
            }
            *n.value = *v;
        }
        const auto unit = lex.quoted();
        if (!unit) {
            return fail(line, sg + ": expected a quoted unit");
        }
        s.unit = *unit;
        if (s.bytesNeeded() > msg.size) {
            return fail(line, sg + ": bits " + std::to_string(s.start_bit) + "|" + std::to_string(s.length) +
                                  (s.byte_order == ByteOrder::Intel ? "@1" : "@0") + " need " +
                                  std::to_string(s.bytesNeeded()) + " bytes, message " + msg.name + " has " +
                                  std::to_string(msg.size));
        }
        if (msg.findSignal(s.name) != nullptr) {
            return fail(line, sg + ": duplicate signal in message " + msg.name);
        }
        if (s.mux_role == MuxRole::Multiplexor) {
            if (msg.multiplexor >= 0) {
                return fail(line, sg + ": second multiplexor in message " + msg.name +
                                      " (extended multiplexing is not supported)");
            }
            msg.multiplexor = static_cast<int>(msg.signals.size());
        }
        msg.signals.push_back(std::move(s));
        return true;
    }

    DbcSignal* findSignal(std::uint64_t raw_id, std::string_view name) {
        const std::uint32_t key = (raw_id & 0x80000000U) != 0
                                      ? static_cast<std::uint32_t>(raw_id)
                                      : (raw_id > kCanMaxStandardId ? static_cast<std::uint32_t>(raw_id | 0x80000000U)
                                                                    : static_cast<std::uint32_t>(raw_id));
        const auto it = m_db.m_by_key.find(key);
        if (it == m_db.m_by_key.end()) {
            return nullptr;
        }
        for (auto& s : m_db.m_messages[it->second].signals) {
            if (s.name == name) {
                return &s;
            }
        }
        return nullptr;
    }

    bool valueNames(Lexer& lex, std::size_t line) {
        m_current = -1;
        const auto raw_id = lex.unsignedInt();
        if (!raw_id) {
            return true;  // VAL_ of an environment variable: skipped
        }
        const auto name = lex.ident();
        if (!name) {
            return fail(line, "VAL_ " + std::to_string(*raw_id) + ": expected a signal name");
        }
        DbcSignal* s = findSignal(*raw_id, *name);
        if (s == nullptr) {
            return fail(line, "VAL_ " + std::to_string(*raw_id) + " " + std::string(*name) + ": unknown signal");
        }
        while (!lex.accept(';') && !lex.atEnd()) {
            const auto v = lex.signedInt();
            const auto text = v ? lex.quoted() : std::nullopt;
            if (!v || !text) {
                return fail(line, "VAL_ " + std::string(*name) + ": expected <value> \"<text>\" pairs");
            }
            s->value_names[*v] = *text;
        }
        return true;
    }

    bool valueType(Lexer& lex, std::size_t line) {
        m_current = -1;
        const auto raw_id = lex.unsignedInt();
        const auto name = raw_id ? lex.ident() : std::nullopt;
        if (!name || !lex.accept(':')) {
            return fail(line, "SIG_VALTYPE_: expected <id> <signal> : <type>");
        }
        const auto type = lex.unsignedInt();
        DbcSignal* s = findSignal(*raw_id, *name);
        if (s == nullptr) {
            return fail(line, "SIG_VALTYPE_ " + std::string(*name) + ": unknown signal");
        }
        if (!type || *type > 2 || (*type == 1 && s->length != 32) || (*type == 2 && s->length != 64)) {
            return fail(line, "SIG_VALTYPE_ " + std::string(*name) +
                                  ": type must be 0, 1 (32-bit float) or 2 (64-bit double) matching the length");
        }
        s->value_type = *type == 1 ? ValueType::Float32 : (*type == 2 ? ValueType::Float64 : ValueType::Integer);
        return true;
    }

    DbcDatabase& m_db;
    DbcDatabase::Mode m_mode;
    int m_current = -1;  // index of the BO_ that SG_ lines belong to; -1 none, -2 skipped pseudo message
    bool m_in_ns_block = false;
    std::string m_first_error;
};

Result<DbcDatabase> DbcDatabase::parse(std::string_view text, std::string_view source_name, Mode mode) {
    DbcDatabase db;
    db.m_source_name = std::string(source_name);
    DbcParser parser(db, mode);
    std::size_t line_no = 0;
    std::size_t pos = 0;
    std::string pending;  // a statement whose quoted string continues on following lines
    QuoteState pending_quotes;
    std::size_t pending_line = 0;
    bool pending_indented = false;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) {
            end = text.size();
        }
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        if (!pending.empty()) {
            pending.push_back('\n');
            pending.append(line);
            pending_quotes.feed("\n");
            pending_quotes.feed(line);
            if (pending_quotes.inString()) {
                continue;
            }
            if (!parser.statement(pending, pending_line, pending_indented)) {
                return Error{parser.firstError()};
            }
            pending.clear();
            continue;
        }
        const bool indented = !line.empty() && (line[0] == ' ' || line[0] == '\t');
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos || line.substr(first, 2) == "//") {
            continue;  // blank line or comment
        }
        QuoteState quotes;
        quotes.feed(line);
        if (quotes.inString()) {
            pending.assign(line);
            pending_quotes = quotes;
            pending_line = line_no;
            pending_indented = indented;
            continue;
        }
        if (!parser.statement(line, line_no, indented)) {
            return Error{parser.firstError()};
        }
    }
    if (!pending.empty()) {
        if (!parser.fail(pending_line, "unterminated quoted string")) {
            return Error{parser.firstError()};
        }
    }
    if (!parser.finish()) {
        return Error{parser.firstError()};
    }
    return db;
}

Result<DbcDatabase> DbcDatabase::load(const std::filesystem::path& path, Mode mode) {
    // Regular files only, opened without blocking, at most kDbcFile.max_bytes read
    // (docs/architecture.md "Untrusted files"): a FIFO or /dev/zero is refused, never waited on.
    std::string problem;
    const std::optional<std::string> text = UntrustedFile::readText(path, kDbcFile, problem);
    if (!text) {
        return Error{problem};
    }
    return parse(*text, path.string(), mode);
}

DbcDatabase DbcDatabase::loadOrThrow(const std::filesystem::path& path, Mode mode) {
    auto r = load(path, mode);
    if (!r) {
        throw DbcError(r.error().message);
    }
    return std::move(r).value();
}

const DbcMessage* DbcDatabase::findMessage(std::uint32_t key) const noexcept {
    const auto it = m_by_key.find(key);
    return it == m_by_key.end() ? nullptr : &m_messages[it->second];
}

const DbcMessage* DbcDatabase::findMessage(std::string_view name) const noexcept {
    const auto it = m_by_name.find(std::string(name));
    return it == m_by_name.end() ? nullptr : &m_messages[it->second];
}

}  // namespace navmap::ipc
