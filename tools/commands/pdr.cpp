// `locus pdr ...`: step counting on accelerometer logs, the Oxford evaluation and tuning, and
// dead-reckoned tracks from full IMU logs (formats in docs/pdr.md). `steps` and `track` also
// take GetSensorData / IPIN logfiles (docs/ipin.md), told apart by their first line.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <thread>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "datasets/pdr_logs.hpp"
#include "datasets/pdr_oxford.hpp"
#include "locus/motion/pdr/pipeline.hpp"

using nlohmann::json;

namespace locus_cli_pdr {
namespace {

using namespace locus;
using namespace locus::tools;
using namespace locus::datasets;

const char* signal_name(pdr::StepSignal s) { return s == pdr::StepSignal::vertical ? "vertical" : "magnitude"; }

json config_json(const pdr::StepDetectorConfig& c) {
    return {{"signal", signal_name(c.signal)},
            {"grid_hz", c.grid_hz},
            {"smoothing_s", c.smoothing_s},
            {"gravity_tau_s", c.gravity_tau_s},
            {"min_threshold", c.min_threshold},
            {"threshold_factor", c.threshold_factor},
            {"rms_tau_s", c.rms_tau_s},
            {"hysteresis", c.hysteresis},
            {"min_peak_to_valley_s", c.min_peak_to_valley_s},
            {"max_peak_to_valley_s", c.max_peak_to_valley_s},
            {"min_step_interval_s", c.min_step_interval_s},
            {"max_gap_s", c.max_gap_s},
            {"bout_steps", c.bout_steps},
            {"bout_regularity", c.bout_regularity},
            {"cadence_min_ratio", c.cadence_min_ratio},
            {"cadence_max_ratio", c.cadence_max_ratio},
            {"max_step_interval_s", c.max_step_interval_s}};
}

// Detector options shared by the commands, so a candidate setting can be tried without a rebuild.
struct DetectorOptions {
    std::string signal;
    pdr::StepDetectorConfig config;

    void add(CLI::App* cmd) {
        cmd->add_option("--signal", signal, "vertical (gravity-aligned) or magnitude")
            ->check(CLI::IsMember({"vertical", "magnitude"}));
        cmd->add_option("--smoothing", config.smoothing_s, "moving-average window, s")->capture_default_str();
        cmd->add_option("--min-threshold", config.min_threshold, "minimum peak/valley threshold, m/s²")->capture_default_str();
        cmd->add_option("--threshold-factor", config.threshold_factor, "threshold as a multiple of the running RMS")
            ->capture_default_str();
        cmd->add_option("--rms-tau", config.rms_tau_s, "time constant of the running RMS, s")->capture_default_str();
        cmd->add_option("--gravity-tau", config.gravity_tau_s, "time constant of the gravity low-pass, s")
            ->capture_default_str();
        cmd->add_option("--max-step-interval", config.max_step_interval_s, "a longer pause ends a bout, s")
            ->capture_default_str();
        cmd->add_option("--hysteresis", config.hysteresis, "fraction of the threshold to confirm an extremum")
            ->capture_default_str();
        cmd->add_option("--min-peak-to-valley", config.min_peak_to_valley_s, "s")->capture_default_str();
        cmd->add_option("--max-peak-to-valley", config.max_peak_to_valley_s, "s")->capture_default_str();
        cmd->add_option("--min-step-interval", config.min_step_interval_s, "s")->capture_default_str();
        cmd->add_option("--bout-steps", config.bout_steps, "regular candidates that start a walking bout (≤ 1: off)")
            ->capture_default_str();
        cmd->add_option("--bout-regularity", config.bout_regularity, "max/min interval ratio within a starting bout")
            ->capture_default_str();
        cmd->add_option("--cadence-min-ratio", config.cadence_min_ratio, "drop candidates sooner than this × cadence")
            ->capture_default_str();
        cmd->add_option("--cadence-max-ratio", config.cadence_max_ratio, "a longer interval ends the bout")
            ->capture_default_str();
    }
    pdr::StepDetectorConfig get() const {
        auto c = config;
        if (!signal.empty()) c.signal = signal == "vertical" ? pdr::StepSignal::vertical : pdr::StepSignal::magnitude;
        return c;
    }
};

template <class F>
auto guarded(F f) {
    try {
        return f();
    } catch (const CommandError&) {
        throw;
    } catch (const std::exception& e) {
        throw CommandError(e.what());
    }
}

// Mean absolute error against a cross-check truth (debounced or alternating foot switches), over
// all traces and per placement. Beside the official figure only; nothing is tuned on it.
struct AltTruthSummary {
    double mean_pct = 0.0;
    std::map<std::string, double> by_placement;
};

AltTruthSummary against(const EvalSummary& s, long OxfordTrace::*truth) {
    AltTruthSummary a;
    std::map<std::string, std::pair<double, int>> acc;
    for (const auto& r : s.traces) {
        const long t = std::max(1L, r.trace->*truth);
        const double e = 100.0 * std::abs(static_cast<double>(r.detected - t)) / static_cast<double>(t);
        a.mean_pct += e;
        auto& p = acc[r.trace->placement];
        p.first += e;
        ++p.second;
    }
    if (!s.traces.empty()) a.mean_pct /= static_cast<double>(s.traces.size());
    for (const auto& [p, v] : acc) a.by_placement[p] = v.first / v.second;
    return a;
}

json summary_json(const EvalSummary& s, bool per_trace) {
    json j;
    if (per_trace) {
        j["traces"] = json::array();
        for (const auto& r : s.traces)
            j["traces"].push_back({{"trace", r.trace->name},
                                   {"user", r.trace->user},
                                   {"placement", r.trace->placement},
                                   {"true_steps", r.trace->true_steps},
                                   {"debounced_true_steps", r.trace->debounced_steps},
                                   {"alternating_true_steps", r.trace->alternating_steps},
                                   {"detected_steps", r.detected},
                                   {"abs_error_pct", r.abs_error_pct}});
    }
    j["mean_abs_error_pct"] = s.mean_abs_error_pct;
    if (!s.traces.empty()) {
        const auto deb = against(s, &OxfordTrace::debounced_steps);
        const auto alt = against(s, &OxfordTrace::alternating_steps);
        j["mean_abs_error_vs_debounced_truth_pct"] = deb.mean_pct;
        j["by_placement_vs_debounced_truth"] = deb.by_placement;
        j["mean_abs_error_vs_alternating_truth_pct"] = alt.mean_pct;
        j["by_placement_vs_alternating_truth"] = alt.by_placement;
    }
    j["by_placement"] = s.placement_mean_pct;
    j["worst_placement_pct"] = s.worst_placement_pct;
    return j;
}

void print_table(const EvalSummary& s, std::ostream& out) {
    out << std::fixed << std::setprecision(2);
    for (const auto& r : s.traces)
        out << std::left << std::setw(38) << r.trace->name << std::right << std::setw(6) << r.trace->true_steps
            << std::setw(6) << r.detected << std::setw(8) << r.abs_error_pct << " %   (debounced truth "
            << r.trace->debounced_steps << ", alternating " << r.trace->alternating_steps << ")\n";
    const auto deb = against(s, &OxfordTrace::debounced_steps);
    const auto alt = against(s, &OxfordTrace::alternating_steps);
    out << "by placement (mean absolute step-count error; official truth, then the debounced and alternating-feet cross-checks):\n";
    for (const auto& [p, e] : s.placement_mean_pct)
        out << "  " << std::left << std::setw(12) << p << std::right << std::setw(7) << e << " %" << std::setw(9)
            << deb.by_placement.at(p) << " %" << std::setw(9) << alt.by_placement.at(p) << " %\n";
    out << "mean over " << s.traces.size() << " traces: " << s.mean_abs_error_pct << " %   (debounced " << deb.mean_pct
        << " %, alternating " << alt.mean_pct << " %)\n";
}

void install_steps(CLI::App& pdr) {
    auto* cmd = pdr.add_subcommand("steps", "Count steps in an accelerometer log (Oxford format, CSV t,ax,ay,az or an IPIN logfile)");
    auto file = std::make_shared<std::string>();
    auto opts = std::make_shared<DetectorOptions>();
    auto times = std::make_shared<bool>(false);
    cmd->add_option("FILE", *file, "accelerometer log, or a GetSensorData / IPIN logfile")->required();
    cmd->add_flag("--times", *times, "also list the step times (s)");
    opts->add(cmd);
    cmd->callback([=] {
        guarded([&] {
            std::optional<datasets::ipin::Log> log;
            std::vector<AccelSample> samples;
            if (datasets::ipin::file_looks_like_log(*file)) {
                log = datasets::ipin::read_log(*file);
                samples = datasets::ipin::accel_samples(*log);
                if (samples.empty()) throw CommandError(*file + ": no ACCE lines");
            } else {
                samples = read_accel_log(*file);
            }
            pdr::StepDetector d(opts->get());
            json step_times = json::array();
            for (const auto& s : samples)
                if (auto e = d.push(s.t_s, s.ax, s.ay, s.az)) step_times.push_back(e->t_s);
            while (auto e = d.poll()) step_times.push_back(e->t_s);
            json j{{"steps", d.steps()},
                   {"duration_s", samples.size() < 2 ? 0.0 : samples.back().t_s - samples.front().t_s}};
            if (log) {
                // Times are on the log's App clock (the ACCE sensor clock moved onto it), as the
                // POSI lines are: the steps between the first and last landmark are the walk's,
                // without the calibration phase's waving before it.
                j["format"] = "ipin";
                if (!log->posi.empty()) {
                    const double from = log->posi.front().app_s, to = log->posi.back().app_s;
                    long walk_steps = 0;
                    for (const auto& t : step_times) walk_steps += t.get<double>() >= from && t.get<double>() <= to;
                    j["posi_span_s"] = to - from;
                    j["steps_in_posi_span"] = walk_steps;
                }
            }
            if (*times) j["step_times_s"] = step_times;
            std::cout << j.dump() << "\n";
            return 0;
        });
    });
}

void install_eval(CLI::App& pdr) {
    auto* cmd = pdr.add_subcommand("eval-oxford",
                                   "Per-trace and per-placement mean absolute step-count error on the Oxford traces");
    auto dir = std::make_shared<std::string>();
    auto opts = std::make_shared<DetectorOptions>();
    auto text = std::make_shared<bool>(false);
    cmd->add_option("DIR", *dir, "oxford-step-counter/optimisation folder")->required();
    auto rate = std::make_shared<double>(0.0);
    cmd->add_flag("--text", *text, "a table instead of JSON");
    cmd->add_option("--rate", *rate, "decimate every trace to about this rate first (Hz; 0 = as recorded)");
    opts->add(cmd);
    cmd->callback([=] {
        guarded([&] {
            auto traces = load_oxford(*dir);
            if (*rate > 0.0)
                for (auto& t : traces) {
                    // Keep the first sample at or after each tick of the target rate: what a phone
                    // delivering a slower sensor stream would have given, timestamps still irregular.
                    std::vector<AccelSample> kept;
                    double next = -1e300;
                    for (const auto& s : t.samples)
                        if (s.t_s >= next) {
                            kept.push_back(s);
                            next = std::max(next + 1.0 / *rate, s.t_s + 0.5 / *rate);
                        }
                    t.samples = std::move(kept);
                }
            std::vector<const OxfordTrace*> ptrs;
            for (const auto& t : traces) ptrs.push_back(&t);
            const auto config = opts->get();
            const auto s = evaluate(ptrs, config);
            if (*text) {
                print_table(s, std::cout);
            } else {
                auto j = summary_json(s, true);
                j["config"] = config_json(config);
                if (*rate > 0.0) j["decimated_to_hz"] = *rate;
                std::cout << j.dump(1) << "\n";
            }
            return 0;
        });
    });
}

void install_tune(CLI::App& pdr) {
    auto* cmd = pdr.add_subcommand("tune-oxford",
                                   "Grid-search the step detector with leave-one-user-out cross-validation");
    auto dir = std::make_shared<std::string>();
    auto threads = std::make_shared<unsigned>(std::max(1u, std::thread::hardware_concurrency()));
    cmd->add_option("DIR", *dir, "oxford-step-counter/optimisation folder")->required();
    cmd->add_option("--threads", *threads, "worker threads")->capture_default_str();
    cmd->callback([=] {
        guarded([&] {
            const auto traces = load_oxford(*dir);
            const auto grid = tuning_grid();
            const auto cv = tune_leave_one_user_out(traces, grid, *threads, [](std::size_t d, std::size_t n) {
                if (d % 100 == 0 || d == n) std::cerr << "\r" << d << "/" << n << " configs" << std::flush;
            });
            std::cerr << "\n";
            json j;
            j["grid_size"] = grid.size();
            j["objective"] = "mean absolute step-count error over the training traces (%)";
            j["leave_one_user_out"] = summary_json(cv.held_out, true);
            for (const auto& [u, c] : cv.chosen) j["leave_one_user_out"]["chosen"][u] = config_json(c);
            j["all_traces_fit"] = summary_json(cv.all_traces_fit, false);
            j["all_traces_fit"]["config"] = config_json(cv.all_traces_best);
            std::cout << j.dump(1) << "\n";
            return 0;
        });
    });
}

void install_track(CLI::App& pdr) {
    auto* cmd = pdr.add_subcommand("track", "Dead-reckon an IMU log (t,sensor,x,y,z) into a track, CSV or GeoJSON");
    struct Args {
        std::string file, floor_file, format = "csv", step_model = "weinberg", sex = "male";
        double x = 0.0, y = 0.0, heading_deg = 0.0, height = 1.75, k = pdr::kWeinbergK, constant = pdr::kConstantStepLength;
        std::optional<double> north_offset_deg;
        double field_ut = 0.0;
        int building = 0, floor = 0;
        DetectorOptions det;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("FILE", a->file, "IMU log, or a GetSensorData / IPIN logfile")->required();
    cmd->add_option("--format", a->format, "csv or geojson")->check(CLI::IsMember({"csv", "geojson"}))->capture_default_str();
    cmd->add_option("--start-x", a->x, "start x, m")->capture_default_str();
    cmd->add_option("--start-y", a->y, "start y, m")->capture_default_str();
    cmd->add_option("--start-heading-deg", a->heading_deg, "heading until the compass gives one")->capture_default_str();
    cmd->add_option("--floor-plan", a->floor_file, "floor JSON (or a whole map, see --building/--floor)");
    cmd->add_option("--building", a->building, "building index in a map file")->capture_default_str();
    cmd->add_option("--floor", a->floor, "floor index in a map file")->capture_default_str();
    cmd->add_option("--north-offset-deg", a->north_offset_deg, "overrides the floor's north_offset_deg");
    cmd->add_option("--field-ut", a->field_ut, "local magnetic field norm, µT (0: learn it from the first 2 s)")
        ->capture_default_str();
    cmd->add_option("--step-length", a->step_model, "weinberg, ssl or constant")
        ->check(CLI::IsMember({"weinberg", "ssl", "constant"}))
        ->capture_default_str();
    cmd->add_option("--k", a->k, "Weinberg K")->capture_default_str();
    cmd->add_option("--height", a->height, "user height for SSL, m")->capture_default_str();
    cmd->add_option("--sex", a->sex, "male or female, for SSL")->check(CLI::IsMember({"male", "female"}));
    cmd->add_option("--constant", a->constant, "constant step length, m")->capture_default_str();
    a->det.add(cmd);
    cmd->callback([a] {
        guarded([&] {
            std::vector<ImuSample> log;
            if (datasets::ipin::file_looks_like_log(a->file)) {
                log = datasets::ipin::imu_samples(datasets::ipin::read_log(a->file));
                if (log.empty()) throw CommandError(a->file + ": no ACCE, GYRO or MAGN lines");
            } else {
                log = read_imu_log(a->file);
            }
            std::optional<FloorPlan> plan;
            double north = 0.0;
            if (!a->floor_file.empty()) plan = read_floor_plan(a->floor_file, a->building, a->floor, north);
            if (a->north_offset_deg) north = *a->north_offset_deg;

            pdr::PipelineConfig pc;
            pc.steps = a->det.get();
            pc.heading.north_offset_deg = north;
            pc.heading.expected_field_ut = a->field_ut;
            pc.start = {a->x, a->y};
            pc.start_heading_rad = a->heading_deg * std::numbers::pi / 180.0;
            pc.step_length.kind = a->step_model == "weinberg" ? pdr::StepLengthKind::weinberg
                                  : a->step_model == "ssl"    ? pdr::StepLengthKind::ssl
                                                              : pdr::StepLengthKind::constant;
            pc.step_length.k = a->k;
            pc.step_length.height_m = a->height;
            pc.step_length.sex = a->sex == "female" ? pdr::Sex::female : pdr::Sex::male;
            pc.step_length.constant_m = a->constant;
            pdr::Pipeline p(pc, plan ? &*plan : nullptr);

            struct Row {
                pdr::TrackPoint tp;
                std::string room;
                std::vector<std::string> pois;
            };
            std::vector<Row> rows;
            auto record = [&](const pdr::TrackPoint& tp) {
                Row r{tp, {}, {}};
                if (const auto* room = p.tracker().room()) r.room = room->name;
                for (const auto* poi : p.tracker().nearby_pois()) r.pois.push_back(poi->name);
                rows.push_back(std::move(r));
            };
            for (const auto& s : log) {
                switch (s.sensor) {
                    case ImuSensor::acc:
                        if (auto tp = p.push_accel(s.t_s, s.v)) record(*tp);
                        break;
                    case ImuSensor::gyro: p.push_gyro(s.t_s, s.v); break;
                    case ImuSensor::mag: p.push_mag(s.t_s, s.v); break;
                    case ImuSensor::step: record(p.push_platform_step(s.t_s)); break;
                }
            }
            while (auto tp = p.poll()) record(*tp);
            const double deg = 180.0 / std::numbers::pi;
            if (a->format == "csv") {
                std::cout << "t,x,y,heading_deg,step_length_m,magnetic_disturbance,room,pois\n";
                std::cout << std::fixed << std::setprecision(3);
                auto quoted = [](const std::string& s) {
                    std::string q = "\"";
                    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
                    return q + "\"";
                };
                for (const auto& r : rows) {
                    std::string pois;
                    for (const auto& n : r.pois) pois += (pois.empty() ? "" : ";") + n;
                    std::cout << r.tp.t_s << "," << r.tp.position.x << "," << r.tp.position.y << ","
                              << r.tp.heading_rad * deg << "," << r.tp.step_length_m << ","
                              << (r.tp.magnetic_disturbance ? 1 : 0) << "," << quoted(r.room) << "," << quoted(pois) << "\n";
                }
            } else {
                // Floor coordinates in metres (docs/spec.md §2.1), not WGS84: a local-CRS GeoJSON.
                json line = json::array({json::array({a->x, a->y})});
                json features = json::array();
                for (const auto& r : rows) {
                    line.push_back(json::array({r.tp.position.x, r.tp.position.y}));
                    features.push_back({{"type", "Feature"},
                                        {"geometry", {{"type", "Point"}, {"coordinates", {r.tp.position.x, r.tp.position.y}}}},
                                        {"properties",
                                         {{"t", r.tp.t_s},
                                          {"heading_deg", r.tp.heading_rad * deg},
                                          {"step_length_m", r.tp.step_length_m},
                                          {"magnetic_disturbance", r.tp.magnetic_disturbance},
                                          {"room", r.room},
                                          {"pois", r.pois}}}});
                }
                features.insert(features.begin(), json{{"type", "Feature"},
                                                       {"geometry", {{"type", "LineString"}, {"coordinates", line}}},
                                                       {"properties", {{"steps", rows.size()},
                                                                       {"distance_m", p.tracker().distance_m()},
                                                                       {"units", "floor metres"}}}});
                std::cout << json{{"type", "FeatureCollection"}, {"features", features}}.dump() << "\n";
            }
            return 0;
        });
    });
}

}  // namespace

LOCUS_COMMAND("pdr", [](CLI::App& app) {
    auto& pdr = group(app, "pdr", "Pedestrian dead reckoning: step counting, Oxford evaluation, tracks");
    install_steps(pdr);
    install_eval(pdr);
    install_tune(pdr);
    install_track(pdr);
});

}  // namespace locus_cli_pdr
