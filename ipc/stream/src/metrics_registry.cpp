// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/stream/metrics_registry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace navmap::ipc {
namespace {

bool validName(const std::string& name, bool label) {
    if (name.empty()) {
        return false;
    }
    for (std::size_t i = 0; i < name.size(); ++i) {
        const char c = name[i];
        const bool alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (!label && c == ':');
        if (!alpha && !(i > 0 && c >= '0' && c <= '9')) {
            return false;
        }
    }
    return true;
}

const char* typeName(MetricsRegistry::Type type) {
    switch (type) {
        case MetricsRegistry::Type::Counter: return "counter";
        case MetricsRegistry::Type::Gauge: return "gauge";
        case MetricsRegistry::Type::Summary: return "summary";
    }
    return "untyped";
}

// HELP text escapes backslash and newline; label values also the double quote.
std::string escape(const std::string& s, bool quote) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        if (c == '\\') {
            out += "\\\\";
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '"' && quote) {
            out += "\\\"";
        } else {
            out += c;
        }
    }
    return out;
}

std::string formatValue(double v) {
    if (std::isnan(v)) {
        return "NaN";
    }
    if (std::isinf(v)) {
        return v > 0 ? "+Inf" : "-Inf";
    }
    char buf[64];
    if (v == std::trunc(v) && std::fabs(v) < 1e15) {
        std::snprintf(buf, sizeof buf, "%.0f", v);  // counters and byte counts stay exact
    } else {
        std::snprintf(buf, sizeof buf, "%.15g", v);
    }
    return buf;
}

}  // namespace

MetricsRegistry::Family& MetricsRegistry::Family::sample(std::initializer_list<Label> labels, double value,
                                                         const char* suffix) {
    return sample(std::vector<Label>(labels), value, suffix);
}

MetricsRegistry::Family& MetricsRegistry::Family::sample(std::vector<Label> labels, double value, const char* suffix) {
    const std::string sfx = suffix != nullptr ? suffix : "";
    if (!sfx.empty() && (m_type != Type::Summary || (sfx != "_sum" && sfx != "_count"))) {
        throw std::logic_error("metric " + m_name + ": suffix " + sfx + " on a " + typeName(m_type));
    }
    for (const auto& [k, v] : labels) {
        if (!validName(k, true) || k.rfind("__", 0) == 0) {
            throw std::logic_error("metric " + m_name + ": bad label name \"" + k + "\"");
        }
        (void)v;
    }
    std::sort(labels.begin(), labels.end());
    for (const auto& s : m_samples) {
        if (s.suffix == sfx && s.labels == labels) {
            throw std::logic_error("metric " + m_name + sfx + ": the same labels twice");
        }
    }
    m_samples.push_back({sfx, std::move(labels), value});
    return *this;
}

MetricsRegistry::Family& MetricsRegistry::add(const std::string& name, Type type, const std::string& help) {
    if (!validName(name, false)) {
        throw std::logic_error("metric family \"" + name + "\": not a Prometheus metric name");
    }
    if (has(name)) {
        throw std::logic_error("metric family " + name + " declared twice");
    }
    m_families.push_back(Family(name, type, help));
    return m_families.back();
}

void MetricsRegistry::append(const MetricsRegistry& other) {
    for (const auto& f : other.m_families) {
        if (has(f.m_name)) {
            throw std::logic_error("metric family " + f.m_name + " declared twice");
        }
        m_families.push_back(f);
    }
}

bool MetricsRegistry::has(const std::string& name) const {
    return std::any_of(m_families.begin(), m_families.end(), [&](const Family& f) { return f.m_name == name; });
}

std::string MetricsRegistry::text() const {
    std::string out;
    for (const auto& f : m_families) {
        out += "# HELP " + f.m_name + " " + escape(f.m_help, false) + "\n";
        out += "# TYPE " + f.m_name + " " + typeName(f.m_type) + "\n";
        for (const auto& s : f.m_samples) {
            out += f.m_name + s.suffix;
            if (!s.labels.empty()) {
                out += '{';
                for (std::size_t i = 0; i < s.labels.size(); ++i) {
                    out += (i > 0 ? "," : "") + s.labels[i].first + "=\"" + escape(s.labels[i].second, true) + "\"";
                }
                out += '}';
            }
            out += ' ' + formatValue(s.value) + '\n';
        }
    }
    return out;
}

}  // namespace navmap::ipc
