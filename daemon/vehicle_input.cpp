// SPDX-License-Identifier: Apache-2.0
#include "vehicle_input.h"

#include <chrono>
#include <stdexcept>

#include "can_sources.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/signal_map.h"

namespace navmap::daemon {

namespace {

// A configured DBC without a single message is not a vehicle database (a wrong file, a truncated
// one): an error naming it. Broken entries of a usable one are skipped (DbcDatabase::Mode::Lenient),
// counted and named, one line per file.
void checkDbc(const ipc::DbcDatabase& db, const std::filesystem::path& path, DecoderSetup* setup) {
    const auto first = [&db] {
        return db.diagnostics().empty() ? std::string() : " (first: " + db.diagnostics().front().message + ")";
    };
    if (db.messages().empty()) {
        throw std::runtime_error(path.string() + ": no message (BO_) in it, not a DBC file" + first());
    }
    if (db.diagnosticCount() == 0 || !setup) return;
    setup->dbc_skipped_entries += db.diagnosticCount();
    setup->warnings.push_back(path.string() + ": " + std::to_string(db.diagnosticCount()) +
                              " broken DBC entries skipped" + first());
}

}  // namespace

ipc::VehicleDecoder VehicleInput::openDecoder(const DaemonConfig& config, const std::filesystem::path& data_dir,
                                              DecoderSetup* setup) {
    // DBC databases: the configured ones, else the shipped GNSS node.
    std::vector<std::filesystem::path> dbc_files = config.dbc_files;
    if (dbc_files.empty()) dbc_files.push_back(data_dir / "navmap.dbc");
    std::vector<std::shared_ptr<const ipc::DbcDatabase>> databases;
    for (const auto& f : dbc_files) {
        auto db = ipc::DbcDatabase::load(f);
        if (!db) throw std::runtime_error(db.error().message);
        checkDbc(db.value(), f, setup);
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
    return std::move(decoder).value();
}

VehicleInput::VehicleInput(const DaemonConfig& config, const map::Projection& projection,
                           const std::filesystem::path& store_path, const std::string& graph_problem,
                           std::shared_ptr<const map::RoadGraph> graph,
                           const std::shared_ptr<ipc::ControlState>& control, const std::filesystem::path& data_dir,
                           const ipc::SimulatorFactory& simulator, double map_reach_m) {
    DecoderSetup setup;
    m_decoder = std::make_unique<ipc::VehicleDecoder>(openDecoder(config, data_dir, &setup));
    m_stats.dbc_skipped_entries = setup.dbc_skipped_entries;
    m_setup_warnings = std::move(setup.warnings);

    VehicleStateConfig vcfg;
    vcfg.gnss_timeout_s = config.stale_after_s;
    vcfg.max_distance_from_origin_m += map_reach_m;
    m_estimator =
        std::make_unique<VehicleStateEstimator>(projection, std::make_shared<const MapMatcher>(std::move(graph)), vcfg);
    m_state.store(m_estimator->snapshot());

    CanSourceSite site;
    site.store_path = store_path;
    site.data_dir = data_dir;
    site.graph_problem = graph_problem;
    site.frame_keys = m_decoder->frameKeys();
    OpenedCanSource opened = openCanSource(config, site, *control, simulator);
    m_source = std::move(opened.source);
    m_stats.source = std::move(opened.name);
    m_stats.error = std::move(opened.error);
}

VehicleInput::~VehicleInput() { stop(); }

void VehicleInput::start() {
    if (m_running.exchange(true)) return;
    if (m_source) m_source->start(ipc::CanClock::now());
    m_thread = std::thread([this] { run(); });
}

void VehicleInput::stop() {
    if (!m_running.exchange(false)) return;
    if (m_thread.joinable()) m_thread.join();
}

void VehicleInput::consume(const ipc::CanFrame& frame) {
    ++m_stats.frames;
    if (!m_decoder->decode(frame, m_update)) return;
    m_estimator->addSample(m_update);
    const auto low_beam = m_update.get(ipc::VssSignal::LowBeam);
    const auto intensity = m_update.get(ipc::VssSignal::LightIntensity);
    if (!low_beam && !intensity) return;
    // A new snapshot only for the frames that carry a light signal (a few per second at most).
    auto light = std::make_shared<AmbientLight>(*m_light.load());
    if (low_beam) {
        light->low_beam = *low_beam >= 0.5;
        light->low_beam_time = m_update.timeOf(ipc::VssSignal::LowBeam);
    }
    if (intensity) {
        light->intensity_pct = *intensity;
        light->intensity_time = m_update.timeOf(ipc::VssSignal::LightIntensity);
    }
    m_light.store(std::move(light));
}

void VehicleInput::setRoute(std::shared_ptr<const RouteLine> route) {
    m_route_update.store(std::make_shared<const RouteUpdate>(RouteUpdate{std::move(route), m_rebase}));
}

void VehicleInput::rebase(const FrameRebase& rebase, std::shared_ptr<const RouteLine> route) {
    m_rebase = std::make_shared<const FrameRebase>(rebase);
    m_epoch = rebase.epoch;
    m_route_update.store(std::make_shared<const RouteUpdate>(RouteUpdate{std::move(route), m_rebase}));
}

EstimatedPose VehicleInput::poseAt(ipc::CanTime t) const {
    EstimatedPose pose = m_state.load()->poseAt(t);
    if (m_rebase && pose.frame_epoch + 1 == m_epoch) {  // the input thread has not taken the rebase yet
        const map::FrameTransform& f = m_rebase->to_frame;
        pose.x = f.scale * pose.x + f.offset_x;
        pose.y = f.scale * pose.y + f.offset_y;
        pose.raw_x = f.scale * pose.raw_x + f.offset_x;
        pose.raw_y = f.scale * pose.raw_y + f.offset_y;
        pose.frame_epoch = m_epoch;
    }
    return pose;
}

void VehicleInput::applyRoute() {
    auto update = m_route_update.load();
    if (!update || update == m_applied_route) return;
    if (update->rebase && update->rebase != m_applied_rebase) {
        const FrameRebase& r = *update->rebase;
        auto graph = std::make_shared<map::RoadGraph>(r.graph ? *r.graph : map::RoadGraph{});
        map::transformRoadGraph(*graph, r.graph_to_frame);
        m_estimator->rebase(r.frame, r.to_frame, std::make_shared<const MapMatcher>(std::move(graph)),
                            r.max_distance_from_origin_m, r.epoch);
        m_applied_rebase = update->rebase;
    }
    m_estimator->setRoute(update->line);
    m_applied_route = std::move(update);
}

void VehicleInput::run() {
    const auto sink = [this](const ipc::CanFrame& f) { consume(f); };
    while (m_running.load()) {
        applyRoute();
        {
            std::lock_guard lock(m_stats_mutex);
            if (m_source) {
                m_source->poll(ipc::CanClock::now(), sink);
                m_source->report(m_source_status);
            }
            m_stats.decoder = m_decoder->counters();
            m_stats.estimator = m_estimator->counters();
        }
        m_state.store(m_estimator->snapshot());
        // 200 Hz is enough for 50-100 Hz CAN; SocketCAN wakes up as soon as frames arrive.
        if (m_source)
            m_source->wait(std::chrono::milliseconds(5));
        else
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

VehicleInputStats VehicleInput::stats() const {
    std::lock_guard lock(m_stats_mutex);
    VehicleInputStats s = m_stats;
    s.can_error_frames = m_source_status.can_error_frames;
    s.can_bus_off = m_source_status.can_bus_off;
    s.can_kernel_drops = m_source_status.can_kernel_drops;
    s.can_state = m_source_status.can_state;
    s.replay_loops = m_source_status.replay_loops;
    s.replay_malformed_lines = m_source_status.replay_malformed_lines;
    s.replay_time_errors = m_source_status.replay_time_errors;
    if (s.error.empty()) s.error = m_source_status.error;
    return s;
}

}  // namespace navmap::daemon
