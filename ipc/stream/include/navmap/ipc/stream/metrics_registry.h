// SPDX-License-Identifier: Apache-2.0
#pragma once
// MetricsRegistry: one scrape of /metrics in the Prometheus text exposition format 0.0.4. Every
// family appears once, with its HELP and TYPE lines, its samples beside it; names carry base
// units (seconds, bytes), as Prometheus' naming rules ask. The frame server and navmapd each add
// their own families to one registry per scrape, so a family can neither be written twice nor
// be split. Declaring a family twice or a sample twice is a programming error: it throws
// std::logic_error naming the family. Not thread-safe; build one per scrape.

#include <deque>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace navmap::ipc {

class MetricsRegistry {
public:
    enum class Type { Counter, Gauge, Summary };

    /// A label name and its value ({"profile", "cluster"}).
    using Label = std::pair<std::string, std::string>;

    /// One metric family: name, type, help and its samples in the order they were added.
    class Family {
    public:
        /// Adds a sample of this family. `suffix` is "" or, for summaries, "_sum" / "_count".
        /// Throws std::logic_error when the same suffix and labels were added before.
        Family& sample(std::initializer_list<Label> labels, double value, const char* suffix = "");
        Family& sample(std::vector<Label> labels, double value, const char* suffix = "");
        Family& sample(double value) { return sample(std::vector<Label>{}, value); }

        [[nodiscard]] const std::string& name() const noexcept { return m_name; }
        [[nodiscard]] Type type() const noexcept { return m_type; }

    private:
        friend class MetricsRegistry;
        struct Sample {
            std::string suffix;
            std::vector<Label> labels;
            double value = 0.0;
        };
        Family(std::string name, Type type, std::string help)
            : m_name(std::move(name)), m_type(type), m_help(std::move(help)) {}
        std::string m_name;
        Type m_type;
        std::string m_help;
        std::vector<Sample> m_samples;
    };

    /// Declares a family. Names match [a-zA-Z_:][a-zA-Z0-9_:]*; throws std::logic_error for a bad
    /// name or a name declared before.
    Family& add(const std::string& name, Type type, const std::string& help);
    Family& counter(const std::string& name, const std::string& help) { return add(name, Type::Counter, help); }
    Family& gauge(const std::string& name, const std::string& help) { return add(name, Type::Gauge, help); }
    Family& summary(const std::string& name, const std::string& help) { return add(name, Type::Summary, help); }

    /// Adds copies of every family of `other`; throws std::logic_error when a name exists here.
    void append(const MetricsRegistry& other);

    /// Whether a family of that name was declared.
    [[nodiscard]] bool has(const std::string& name) const;
    [[nodiscard]] std::size_t size() const noexcept { return m_families.size(); }

    /// The exposition text: per family "# HELP", "# TYPE", then its samples. Label values are
    /// escaped (\\, \", \n); whole numbers print without exponent or fraction, others with 15
    /// significant digits, non-finite ones as NaN, +Inf, -Inf.
    [[nodiscard]] std::string text() const;

private:
    std::deque<Family> m_families;  // references stay valid as families are added
};

}  // namespace navmap::ipc
