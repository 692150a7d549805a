#include "vehicle_input.h"

#include <chrono>
#include <stdexcept>

#include "navmap/ipc/candump_file_source.h"
#include "navmap/ipc/dbc_database.h"
#include "navmap/ipc/replayer.h"
#include "navmap/ipc/signal_map.h"
#include "navmap/ipc/socketcan_source.h"
#include "navmap/sim/drive_simulator.h"

namespace navmap::daemon {

VehicleInput::VehicleInput(const DaemonConfig& config, const map::Projection& projection,
                           const std::filesystem::path& store_path, const std::string& graph_problem,
                           std::shared_ptr<const map::RoadGraph> graph, std::shared_ptr<ipc::ControlState> control,
                           const std::filesystem::path& data_dir)
    : m_control(std::move(control)) {
    // DBC databases: the configured ones, else the shipped GNSS node.
    std::vector<std::filesystem::path> dbc_files = config.dbc_files;
    if (dbc_files.empty()) dbc_files.push_back(data_dir / "navmap.dbc");
    std::vector<std::shared_ptr<const ipc::DbcDatabase>> databases;
    for (const auto& f : dbc_files) {
        auto db = ipc::DbcDatabase::load(f);
        if (!db) throw std::runtime_error(db.error().message);
        databases.push_back(std::make_shared<const ipc::DbcDatabase>(std::move(db).value()));
    }
    ipc::SignalMap signals = ipc::SignalMap::navmapDefaults();
    if (!config.signal_map_toml.empty()) {
        auto m = ipc::SignalMap::fromToml(config.signal_map_toml, "[[can.signal]]", "can.signal");
        if (!m) throw std::runtime_error(m.error().message);
        signals = std::move(m).value();
    }
    auto decoder = ipc::VehicleDecoder::create(databases, signals);
    if (!decoder) throw std::runtime_error(decoder.error().message);
    m_decoder = std::make_unique<ipc::VehicleDecoder>(std::move(decoder).value());

    VehicleStateConfig vcfg;
    vcfg.gnssTimeoutS = config.stale_after_s;
    m_estimator = std::make_unique<VehicleStateEstimator>(projection, std::make_shared<const MapMatcher>(std::move(graph)), vcfg);
    m_state.store(m_estimator->snapshot());

    ipc::ReplayOptions replay;
    replay.loop = true;
    replay.restamp = true;
    switch (config.input) {
        case InputSource::Replay: {
            // Streamed: memory stays bounded whatever the file. The replayer reads up to the first
            // frame now, so a file that is no candump log (binary data, /dev/zero, nothing but
            // malformed lines) fails here with one error naming it.
            auto source = ipc::CandumpFileSource::open(config.replay_log);
            if (!source) throw std::runtime_error(source.error().message);
            m_replay_file = source.value().get();
            replay.speed = config.replay_speed;
            replay.loop = config.replay_loop;
            m_replayer = std::make_unique<ipc::Replayer>(std::move(source).value(), replay);
            if (const std::string error = m_replayer->error(); !error.empty()) throw std::runtime_error(error);
            if (m_replayer->finished()) {
                std::fprintf(stderr, "<4>navmapd: %s: no CAN frames to replay\n", config.replay_log.c_str());
            }
            m_stats.source = "replay " + config.replay_log.string();
            break;
        }
        case InputSource::Sim: {
            m_stats.source = "sim " + config.sim_from + " -> " + config.sim_to;
            if (!graph_problem.empty()) {
                // The map still renders; the simulated car has no road to drive on.
                m_stats.error = "the simulator cannot plan a route: road graph unavailable: " + graph_problem;
                std::fprintf(stderr, "<4>navmapd: %s: %s\n", m_stats.source.c_str(), m_stats.error.c_str());
                break;
            }
            sim::DriveRequest request;
            request.store = store_path;
            request.dbc = data_dir / "navmap.dbc";
            request.from = config.sim_from;
            request.to = config.sim_to;
            const sim::DriveSimulator simulator = sim::DriveSimulator::create(request);
            replay.speed = config.sim_speed_factor;
            m_replayer = simulator.replayer(replay);
            // The simulated HMI sets the route it drives, as set_route over the control socket would.
            ipc::SetRouteCommand route;
            route.routeId = "sim";
            for (const auto& p : simulator.route().line) {
                double lat = 0, lon = 0;
                projection.reverse(p.position, lat, lon);
                route.points.push_back({lat, lon});
            }
            if (auto st = m_control->setRoute(route); !st) throw std::runtime_error("simulated route: " + st.message());
            break;
        }
        case InputSource::SocketCan: {
            ipc::SocketCanOptions o;
            o.interfaceName = config.can_interface;
            o.frameKeys = m_decoder->frameKeys();
            m_can = std::make_unique<ipc::SocketCanSource>(o);
            m_stats.source = "socketcan " + config.can_interface;
            break;
        }
    }
}

VehicleInput::~VehicleInput() { stop(); }

void VehicleInput::start() {
    if (m_running.exchange(true)) return;
    if (m_replayer) m_replayer->reset(ipc::CanClock::now());
    m_thread = std::thread([this] { run(); });
}

void VehicleInput::stop() {
    if (!m_running.exchange(false)) return;
    if (m_thread.joinable()) m_thread.join();
}

void VehicleInput::consume(const ipc::CanFrame& frame) {
    ++m_stats.frames;
    if (m_decoder->decode(frame, m_update)) m_estimator->addSample(m_update);
}

void VehicleInput::run() {
    const auto sink = [this](const ipc::CanFrame& f) { consume(f); };
    while (m_running.load()) {
        // Route changes from the control socket (applied here: the estimator's thread).
        if (const auto route = m_control->route(); route && route->version != m_route_version) {
            m_route_version = route->version;
            std::vector<std::pair<double, double>> pts;
            for (const auto& p : route->points) pts.emplace_back(p.lat, p.lon);
            if (pts.size() >= 2) m_estimator->setRouteLatLon(route->id, pts);
            else m_estimator->setRoute(nullptr);
        }
        {
            std::lock_guard lock(m_stats_mutex);
            if (m_replayer) {
                m_replayer->advanceTo(ipc::CanClock::now(), sink);
                m_stats.replay_loops = m_replayer->loops();
                m_stats.replay_time_errors = m_replayer->timeErrors();
                if (m_replay_file) reportReplayFile();
            } else if (m_can) {
                m_can->poll(sink);
                const auto& st = m_can->status();
                m_stats.can_error_frames = st.errorFrames;
                m_stats.can_bus_off = st.busOff;
                m_stats.can_kernel_drops = st.kernelDrops;
                m_stats.can_state = st.state == ipc::SocketCanStatus::State::Open ? "open" : "retrying: " + st.lastError;
            }
            m_stats.decoder = m_decoder->counters();
            m_stats.estimator = m_estimator->counters();
        }
        m_state.store(m_estimator->snapshot());
        // 200 Hz is enough for 50-100 Hz CAN; SocketCAN wakes up as soon as frames arrive.
        if (m_can) m_can->waitReadable(std::chrono::milliseconds(5));
        else std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

// Malformed lines (the first is logged, all are counted) and a replay that stopped early (logged
// once; the position then turns stale and shows as lost).
void VehicleInput::reportReplayFile() {
    const auto& reader = m_replay_file->reader();
    m_stats.replay_malformed_lines = reader.counters().malformed;
    if (!m_logged_malformed && !reader.errors().empty()) {
        m_logged_malformed = true;
        std::fprintf(stderr, "<4>navmapd: malformed candump line skipped: %s (all are counted in status)\n",
                     reader.errors().front().message.c_str());
    }
    if (m_stats.error.empty() && m_replayer->finished()) {
        m_stats.error = m_replayer->error();
        if (!m_stats.error.empty()) {
            m_stats.error = "replay stopped: " + m_stats.error;
            std::fprintf(stderr, "<3>navmapd: %s\n", m_stats.error.c_str());
        }
    }
}

VehicleInputStats VehicleInput::stats() const {
    std::lock_guard lock(m_stats_mutex);
    return m_stats;
}

}  // namespace navmap::daemon
