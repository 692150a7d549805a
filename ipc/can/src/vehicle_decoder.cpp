// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/vehicle_decoder.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace navmap::ipc {
namespace {

bool endsWith(std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

/// A message named by name or by id ("0x415", "1045").
const DbcMessage* findMessage(const DbcDatabase& db, const std::string& ref) {
    if (const DbcMessage* m = db.findMessage(std::string_view(ref))) {
        return m;
    }
    std::uint64_t v = 0;
    std::size_t i = 0;
    int base = 10;
    if (ref.size() > 2 && ref[0] == '0' && (ref[1] == 'x' || ref[1] == 'X')) {
        base = 16;
        i = 2;
    }
    if (i >= ref.size()) {
        return nullptr;
    }
    for (; i < ref.size(); ++i) {
        const char c = ref[i];
        int d = -1;
        if (c >= '0' && c <= '9') {
            d = c - '0';
        } else if (base == 16 && std::isxdigit(static_cast<unsigned char>(c)) != 0) {
            d = (std::tolower(static_cast<unsigned char>(c)) - 'a') + 10;
        }
        if (d < 0 || v > 0xFFFFFFFFULL) {
            return nullptr;
        }
        v = v * static_cast<unsigned>(base) + static_cast<unsigned>(d);
    }
    const auto id = static_cast<std::uint32_t>(v & 0x1FFFFFFFU);
    const bool extended = (v & 0x80000000ULL) != 0 || id > kCanMaxStandardId;
    return db.findMessage(extended ? (id | 0x80000000U) : id);
}

}  // namespace

Result<VehicleDecoder> VehicleDecoder::create(std::vector<std::shared_ptr<const DbcDatabase>> databases,
                                              const SignalMap& map) {
    VehicleDecoder dec;
    dec.m_databases = std::move(databases);
    const auto& mappings = map.mappings();
    dec.m_stats.resize(mappings.size());
    for (std::size_t i = 0; i < mappings.size(); ++i) {
        const SignalMapping& m = mappings[i];
        const std::string what = std::string(vssName(m.target)) + " <- " + m.message + "." + m.signal;
        const DbcMessage* msg = nullptr;
        for (const auto& db : dec.m_databases) {
            if (!m.dbc.empty() && !endsWith(db->sourceName(), m.dbc)) {
                continue;
            }
            msg = findMessage(*db, m.message);
            if (msg != nullptr) {
                break;
            }
        }
        if (msg == nullptr) {
            return Error{"signal map " + what + ": message '" + m.message + "' is in none of the DBC files" +
                         (m.dbc.empty() ? std::string() : " named '" + m.dbc + "'")};
        }
        Plan plan;
        plan.message = msg;
        plan.signal = msg->findSignal(m.signal);
        if (plan.signal == nullptr) {
            return Error{"signal map " + what + ": message " + msg->name + " has no signal '" + m.signal + "'"};
        }
        if (!m.sign_signal.empty()) {
            plan.sign_signal = msg->findSignal(m.sign_signal);
            if (plan.sign_signal == nullptr) {
                return Error{"signal map " + what + ": message " + msg->name + " has no sign signal '" + m.sign_signal +
                             "'"};
            }
        }
        const std::string& unit = m.unit.empty() ? plan.signal->unit : m.unit;
        const auto factor = unitConversion(unit, m.target);
        if (!factor) {
            return Error{"signal map " + what + ": cannot convert unit '" + unit + "' to '" +
                         std::string(vssUnit(m.target)) + "' (set 'unit' in the mapping)"};
        }
        plan.target = m.target;
        plan.unit_factor = *factor;
        plan.scale = m.scale;
        plan.bias = m.bias;
        plan.mapping_index = i;
        dec.m_plans[msg->key()].push_back(plan);
    }
    return dec;
}

void VehicleDecoder::reject(const Plan& plan, std::string why) {
    ++m_counters.rejected;
    MappingStats& st = m_stats[plan.mapping_index];
    ++st.rejected;
    st.last_rejection = std::move(why);
}

bool VehicleDecoder::decode(const CanFrame& frame, VehicleSample& update) {
    ++m_counters.frames;
    update = VehicleSample{};
    if (frame.error() || frame.rtr()) {
        ++m_counters.ignored_frames;
        return false;
    }
    const auto it = m_plans.find(frame.key());
    if (it == m_plans.end()) {
        return false;
    }
    ++m_counters.matched_frames;
    const std::span<const std::uint8_t> data(frame.data.data(), std::min<std::size_t>(frame.len, kCanMaxFdLen));
    bool any = false;
    bool short_counted = false;
    for (const Plan& plan : it->second) {
        const DbcSignal& sig = *plan.signal;
        if (!plan.message->isPresent(sig, data)) {
            continue;  // another multiplexed page
        }
        const auto physical = sig.decode(data);
        if (!physical) {
            if (!short_counted) {
                ++m_counters.short_frames;
                short_counted = true;
            }
            reject(plan, "frame has " + std::to_string(frame.len) + " bytes, " + sig.name + " needs " +
                             std::to_string(sig.bytesNeeded()));
            continue;
        }
        if (!sig.inRange(*physical)) {
            reject(plan, sig.name + " = " + std::to_string(*physical) + " is outside the DBC range [" +
                             std::to_string(sig.minimum) + ", " + std::to_string(sig.maximum) + "]");
            continue;
        }
        double value = *physical * plan.unit_factor * plan.scale + plan.bias;
        if (plan.sign_signal != nullptr) {
            const auto sign = plan.sign_signal->decode(data);
            if (!sign) {
                reject(plan, "sign signal " + plan.sign_signal->name + " is missing");
                continue;
            }
            if (*sign != 0.0) {
                value = -value;
            }
        }
        if (!std::isfinite(value) || value < vssMinimum(plan.target) || value > vssMaximum(plan.target)) {
            reject(plan, std::string(vssName(plan.target)) + " = " + std::to_string(value) +
                             " is outside the plausible range [" + std::to_string(vssMinimum(plan.target)) + ", " +
                             std::to_string(vssMaximum(plan.target)) + "]");
            continue;
        }
        if (plan.target == VssSignal::GnssCounter && sig.length < 64) {
            const std::uint64_t modulo = std::uint64_t{1} << sig.length;
            const auto counter = static_cast<std::uint64_t>(value) % modulo;
            if (m_last_counter) {
                const std::uint64_t expected = (*m_last_counter + 1U) % modulo;
                m_counters.counter_gaps += (counter + modulo - expected) % modulo;
            }
            m_last_counter = counter;
        }
        update.set(plan.target, value, frame.timestamp);
        ++m_stats[plan.mapping_index].accepted;
        ++m_counters.values;
        any = true;
    }
    if (any) {
        update.source_time = frame.timestamp;
        m_latest.merge(update);
    }
    return any;
}

std::vector<std::uint32_t> VehicleDecoder::frameKeys() const {
    std::vector<std::uint32_t> keys;
    keys.reserve(m_plans.size());
    for (const auto& [key, plans] : m_plans) {
        keys.push_back(key);
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

}  // namespace navmap::ipc
