// Live tracks fused by the Kalman filters of the Kalman-fusion paper (docs/spec.md §8) over HTTP
// against the real server: a floor with six transmitters, a walk along a known path, its PDR steps
// and the scans the log-distance model gives along it; the server's fused fixes are client-lib's
// ranging and Kalman filter run in-process on the same inputs, and end near the truth. Bad input
// (unknown fusion, bad fusion_options, a scan hearing two known transmitters, a map with none) is
// refused with nothing written, and a restarted server (or, on PostgreSQL, another server sharing
// the database) resumes at the latest stored fix. Eigen first: cpp-httplib pulls in <resolv.h>,
// whose `_res` macro breaks Eigen's headers.
#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/ranging_ekf.hpp"
#include "locus/motion/fusion/ranging_fix.hpp"

#include <httplib.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <optional>
#include <vector>

#include "hierarchy.hpp"
#include "locus/motion/pdr/heading_convention.hpp"
#include "locus/ranging/path_loss.hpp"
#include "locus/ranging/trilateration.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_ranging_test {
namespace {

using locus::Point;
using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::unix_now;
using nlohmann::json;
namespace fusion = locus::fusion;
namespace ranging = locus::ranging;

constexpr double kPhoneHeight = 1.2;  // the server's default: a transmitter's z is measured against it

struct Tx {
    std::string bssid;
    double x, y, z, tx_power, exponent;
    ranging::Transmitter model() const { return {{x, y}, z - kPhoneHeight, {tx_power, exponent}}; }
};

// Six transmitters around and inside a 13 m × 12 m area of the hierarchy's 30 m × 20 m floor,
// so that every point of the walk has three within the Kalman-fusion paper's 10 m cutoff.
const std::vector<Tx> kTxs = {{"aa:10:00:00:00:01", 1.0, 1.0, 2.5, -40.0, 2.0},
                              {"aa:10:00:00:00:02", 14.0, 1.0, 2.5, -42.0, 2.1},
                              {"aa:10:00:00:00:03", 14.0, 13.0, 2.5, -41.0, 2.0},
                              {"aa:10:00:00:00:04", 1.0, 13.0, 2.5, -39.0, 1.9},
                              {"aa:10:00:00:00:05", 7.0, 7.0, 2.8, -40.0, 2.0},
                              {"aa:10:00:00:00:06", 11.0, 7.0, 2.2, -41.0, 2.0}};

Response call(const ServerProcess& s, const std::string& method, const std::string& path, const std::string& token = "",
              const std::string& body = "") {
    httplib::Client c("127.0.0.1", s.port());
    c.set_read_timeout(10, 0);
    httplib::Headers h;
    if (!token.empty()) h.emplace("X-Track-Token", token);
    httplib::Result r = method == "GET" ? c.Get(path.c_str(), h) : c.Post(path.c_str(), h, body, "application/json");
    Response out;
    if (!r) return out;
    out.status = r->status;
    out.raw = r->body;
    out.body = json::parse(r->body, nullptr, false);
    return out;
}

void add_transmitters(const ServerProcess& s, std::int64_t floor, std::size_t n = kTxs.size()) {
    for (std::size_t i = 0; i < n; ++i) {
        const Tx& t = kTxs[i];
        const json body = {{"type", "wifi"}, {"bssid", t.bssid}, {"x", t.x}, {"y", t.y}, {"z", t.z}, {"tx_power", t.tx_power},
                           {"path_loss_exponent", t.exponent}};
        ASSERT_EQ(s.post("/v1/floors/" + std::to_string(floor) + "/transmitters", body).status, 201);
    }
}

// The walk: from (3, 3), 12 steps of 0.7 m east, then 12 north; a step a second from t0 + 1, a
// scan every 2 s from t0 (none at a step's t), each reading the model's RSS plus a fixed
// ±2 dB pattern of shadowing.
struct Walk {
    double t0 = 0;
    std::vector<json> steps, scans;
    std::vector<std::pair<double, Point>> truth;  // at each step
    Point end;
};

Walk make_walk(double t0) {
    Walk w;
    w.t0 = t0;
    Point at{3.0, 3.0};
    const auto scan = [&](double t, Point p, int k) {
        json readings = json::array();
        for (std::size_t i = 0; i < kTxs.size(); ++i) {
            const auto m = kTxs[i].model();
            const double d = std::hypot(locus::distance(m.at, p), m.dz);
            const double shadow = 2.0 * std::sin(1.7 * static_cast<double>(k) + 2.3 * static_cast<double>(i));
            readings.push_back({{"type", "wifi"}, {"bssid", kTxs[i].bssid}, {"rss", ranging::rss_at(m.model, d) + shadow}});
        }
        w.scans.push_back({{"t", t}, {"readings", readings}});
    };
    scan(t0, at, 0);
    for (int i = 1; i <= 24; ++i) {
        const double heading = i <= 12 ? 90.0 : 0.0;
        at = locus::pdr::step(at, 0.7, heading * std::numbers::pi / 180.0);
        w.steps.push_back({{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", heading}});
        w.truth.push_back({t0 + i, at});
        if (i % 2 == 1) scan(t0 + i + 0.5, locus::pdr::step(at, 0.35, heading * std::numbers::pi / 180.0), i);
    }
    w.end = at;
    return w;
}

// A filter's answers to the inputs of one request in the server's order (by t, a radio fix
// before a step of equal t).
template <class Filter>
std::vector<json> in_server_order(Filter& f, const std::vector<json>& steps, const std::vector<json>& scans) {
    std::vector<json> out;
    std::size_t i = 0, j = 0;
    while (i < steps.size() || j < scans.size()) {
        if (j < scans.size() && (i >= steps.size() || scans[j]["t"].get<double>() <= steps[i]["t"].get<double>())) out.push_back(f.scan(scans[j++]));
        else out.push_back(f.step(steps[i++]));
    }
    return out;
}

// What the server does, in-process: each scan ranged (in the order its readings came, as the
// server's query keeps them), client-lib's Kalman filter started at the first fix with the
// fix's own σ, steps as control input.
struct Expected {
    fusion::RangingKalmanConfig config;
    bool multilateration = false;
    std::optional<fusion::KalmanFilter> kf;
    json heading_deg = nullptr;  // the last step's, answered raw

    json fused(double t) const {
        const Point p = kf->position();
        json f = {{"t", t}, {"x", p.x}, {"y", p.y}, {"accuracy_m", std::sqrt(kf->covariance().trace() / 2.0)}};
        if (!heading_deg.is_null()) f["heading_deg"] = heading_deg;
        return f;
    }
    // A server resuming the track starts the filter at its latest stored fix, σ its accuracy.
    void resume(const json& latest) {
        fusion::KalmanConfig c = config.kalman;
        c.initial_sigma_m = latest["accuracy_m"].get<double>();
        kf.emplace(Point{latest["x"].get<double>(), latest["y"].get<double>()}, c);
        heading_deg = latest.value("heading_deg", json());
    }
    json scan(const json& s) {
        std::vector<ranging::Heard> heard;
        for (const auto& r : s["readings"])
            for (const Tx& t : kTxs)
                if (t.bssid == r["bssid"]) heard.push_back({t.model(), r["rss"].get<double>()});
        const auto f = multilateration ? ranging::multilaterate(heard) : ranging::trilaterate(heard);
        EXPECT_TRUE(f.has_value());
        if (!f) return {};
        const Eigen::Matrix2d r = fusion::ranging_measurement_noise(*f, config);
        if (!kf) {
            fusion::KalmanConfig c = config.kalman;
            c.initial_sigma_m = std::sqrt(r.trace() / 2.0);
            kf.emplace(f->at, c);
        } else {
            kf->update(f->at, r);
        }
        return fused(s["t"].get<double>());
    }
    json step(const json& s) {
        heading_deg = s["heading_deg"];
        kf->predict(locus::pdr::step({0.0, 0.0}, s["length_m"].get<double>(), s["heading_deg"].get<double>() * std::numbers::pi / 180.0));
        return fused(s["t"].get<double>());
    }
    std::vector<json> run(const std::vector<json>& steps, const std::vector<json>& scans) { return in_server_order(*this, steps, scans); }
};

// ekf_ranging in-process: fusion::RangingEkf over the map's transmitters (ids as the server keys
// them), started at the first scan's multilateration fix with the fix's σ (at least 0.5 m), or
// at a stored fix when resumed; later scans' readings are its measurements, steps its control.
struct ExpectedEkf {
    fusion::RangingEkfConfig config;
    std::optional<fusion::RangingEkf> ekf;
    std::optional<double> heading_deg;  // the last step's; answered less the filter's heading bias

    static std::vector<fusion::RangingAnchor> anchors() {
        std::vector<fusion::RangingAnchor> out;
        for (const Tx& t : kTxs) out.push_back({"wifi|" + t.bssid, t.model()});
        return out;
    }
    void start(Point at, double sigma) {
        fusion::RangingEkfConfig c = config;
        c.initial_sigma_m = sigma;
        ekf.emplace(at, anchors(), c);
    }
    void resume(const json& latest) {
        start({latest["x"].get<double>(), latest["y"].get<double>()}, latest["accuracy_m"].get<double>());
        if (latest.contains("heading_deg")) heading_deg = latest["heading_deg"].get<double>();
    }
    json fused(double t) const {
        const Point p = ekf->position();
        json f = {{"t", t}, {"x", p.x}, {"y", p.y}, {"accuracy_m", std::sqrt(ekf->position_covariance().trace() / 2.0)}};
        // The bias turns the steps counter-clockwise; headings are clockwise.
        if (heading_deg) f["heading_deg"] = *heading_deg - ekf->heading_bias_rad() * 180.0 / std::numbers::pi;
        return f;
    }
    json scan(const json& s) {
        const double t = s["t"].get<double>();
        std::vector<ranging::Heard> heard;
        std::vector<fusion::AnchorReading> readings;
        for (const auto& r : s["readings"])
            for (const Tx& tx : kTxs)
                if (tx.bssid == r["bssid"]) {
                    heard.push_back({tx.model(), r["rss"].get<double>()});
                    readings.push_back({"wifi|" + tx.bssid, t, r["rss"].get<double>()});
                }
        if (!ekf) {
            const auto f = ranging::multilaterate(heard);
            EXPECT_TRUE(f.has_value());
            if (!f) return {};
            start(f->at, std::max(std::sqrt(fusion::ranging_covariance(*f).trace() / 2.0), 0.5));
        } else {
            ekf->update(readings);
        }
        return fused(t);
    }
    json step(const json& s) {
        heading_deg = s["heading_deg"].get<double>();
        const double heading = *heading_deg * std::numbers::pi / 180.0;
        ekf->predict(locus::pdr::step({0.0, 0.0}, s["length_m"].get<double>(), heading), s["t"].get<double>());
        return fused(s["t"].get<double>());
    }
    std::vector<json> run(const std::vector<json>& steps, const std::vector<json>& scans) { return in_server_order(*this, steps, scans); }
};

void expect_same(const json& got, const std::vector<json>& expected) {
    ASSERT_EQ(got.size(), expected.size()) << got.dump();
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(got[i]["t"].get<double>(), expected[i]["t"].get<double>()) << i;
        EXPECT_NEAR(got[i]["x"].get<double>(), expected[i]["x"].get<double>(), 1e-9) << i;
        EXPECT_NEAR(got[i]["y"].get<double>(), expected[i]["y"].get<double>(), 1e-9) << i;
        EXPECT_NEAR(got[i]["accuracy_m"].get<double>(), expected[i]["accuracy_m"].get<double>(), 1e-9) << i;
        ASSERT_EQ(got[i].contains("heading_deg"), expected[i].contains("heading_deg")) << i << ": " << got[i].dump();
        if (expected[i].contains("heading_deg")) {  // as angles: the server answers in [0, 360)
            const double h = got[i]["heading_deg"].get<double>();
            EXPECT_GE(h, 0.0) << i;
            EXPECT_LT(h, 360.0) << i;
            EXPECT_NEAR(std::remainder(h - expected[i]["heading_deg"].get<double>(), 360.0), 0.0, 1e-9) << i;
        }
    }
}

std::vector<json> slice(const std::vector<json>& v, double from_t, double to_t) {
    std::vector<json> out;
    for (const auto& j : v)
        if (j["t"].get<double>() >= from_t && j["t"].get<double>() < to_t) out.push_back(j);
    return out;
}

json body(const std::vector<json>& steps, const std::vector<json>& scans) {
    json b = json::object();
    if (!steps.empty()) b["steps"] = steps;
    if (!scans.empty()) b["scans"] = scans;
    return b;
}

std::size_t stored_fixes(const ServerProcess& s, const Track& t) {
    return body_of(call(s, "GET", t.path(), t.token))["fixes"].get<std::size_t>();
}

// The walk posted to `t` in two requests split at `mid`: each answer's fused fixes are `e`'s
// (client-lib in-process) on the same inputs, and the first gives a scan fix a scan, on `floor`.
struct TwoAnswers {
    json first, rest;
    std::vector<json> expected_rest;
};

template <class Filter>
TwoAnswers post_in_two(const ServerProcess& s, const Track& t, const Walk& w, double mid, std::int64_t floor, Filter& e) {
    TwoAnswers out;
    const auto first_steps = slice(w.steps, w.t0, mid), first_scans = slice(w.scans, w.t0, mid);
    out.first = body_of(call(s, "POST", t.path("/steps"), t.token, body(first_steps, first_scans).dump()));
    expect_same(out.first["fused"], e.run(first_steps, first_scans));
    EXPECT_EQ(out.first["scan_fixes"].size(), first_scans.size());
    for (const auto& f : out.first["scan_fixes"]) EXPECT_EQ(f["floor_id"], floor);
    const auto rest_steps = slice(w.steps, mid, 1e300), rest_scans = slice(w.scans, mid, 1e300);
    out.rest = body_of(call(s, "POST", t.path("/steps"), t.token, body(rest_steps, rest_scans).dump()));
    out.expected_rest = e.run(rest_steps, rest_scans);
    expect_same(out.rest["fused"], out.expected_rest);
    return out;
}

// What the resume tests share: on `s`, the hierarchy with the transmitters, a track of `fusion`
// (and `options`), and the walk's steps and scans before t0 + `mid_s` posted to it.
struct HalfWalked {
    locus::testing::Hierarchy h;
    Walk w;
    Track t;
    double mid = 0;
};

HalfWalked walk_half(const ServerProcess& s, const std::string& fusion, const json& options, double mid_s) {
    HalfWalked hw{locus::testing::make_hierarchy(s), make_walk(std::floor(unix_now()) - 60), {}, 0};
    add_transmitters(s, hw.h.floor);
    json opened = {{"map_id", hw.h.map}, {"fusion", fusion}};
    if (!options.is_null()) opened["fusion_options"] = options;
    hw.t = open_track(s, opened);
    hw.mid = hw.w.t0 + mid_s;
    const auto& w = hw.w;
    body_of(call(s, "POST", hw.t.path("/steps"), hw.t.token,
                 body(slice(w.steps, w.t0, hw.mid), slice(w.scans, w.t0, hw.mid)).dump()));
    return hw;
}

// Restarts `s`, checks the track kept its fusion and options, and returns its latest stored fix.
json restart(ServerProcess& s, const HalfWalked& hw, const std::string& fusion, const json& options) {
    s.stop();
    s.start();
    const json info = body_of(call(s, "GET", hw.t.path(), hw.t.token));
    EXPECT_EQ(info["fusion"], fusion);
    EXPECT_EQ(info["fusion_options"], options);
    return info["latest"];
}

// On `other` (sharing the database): the latest stored fix, the last step's (t0 + 10), then the
// answer to the rest of the walk posted there.
std::pair<json, json> finish_on(const ServerProcess& other, const HalfWalked& hw) {
    const json latest = body_of(call(other, "GET", hw.t.path(), hw.t.token))["latest"];
    EXPECT_EQ(latest["t"].get<double>(), hw.w.t0 + 10);
    const auto rest_steps = slice(hw.w.steps, hw.mid, 1e300), rest_scans = slice(hw.w.scans, hw.mid, 1e300);
    return {latest, body_of(call(other, "POST", hw.t.path("/steps"), hw.t.token, body(rest_steps, rest_scans).dump()))};
}

// Both Kalman methods, in two requests each: the server's fused fixes are client-lib's on the
// same ranged scans and steps (to 1e-9), end within 1.5 m of the truth, and are stored.
TEST(ServerTracksRanging, KalmanTracksFuseScansAsClientLibDoes) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    add_transmitters(s, h.floor);
    const Walk w = make_walk(std::floor(unix_now()) - 60);
    const double mid = w.t0 + 12.2;
    struct Case {
        const char* fusion;
        json options;
        fusion::RangingKalmanConfig config;
        bool multilateration;
    };
    auto trilateration_config = fusion::trilateration_kalman_config();
    trilateration_config.fixed_r_sigma_m = 2.0;
    trilateration_config.kalman.step_sigma_floor_m = 0.25;
    std::vector<Case> cases = {{"kalman_trilateration", {{"r_sigma_m", 2.0}, {"q_sigma_m", 0.25}}, trilateration_config, false},
                               {"kalman_ranging", nullptr, fusion::ranging_kalman_config(), true}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.fusion);
        json opened = {{"map_id", h.map}, {"fusion", c.fusion}};
        if (!c.options.is_null()) opened["fusion_options"] = c.options;
        const Track t = open_track(s, opened);
        const json info = body_of(call(s, "GET", t.path(), t.token));
        EXPECT_EQ(info["fusion"], c.fusion);
        if (!c.options.is_null()) EXPECT_EQ(info["fusion_options"], c.options);
        else EXPECT_FALSE(info.contains("fusion_options"));
        Expected e{c.config, c.multilateration, std::nullopt};
        const auto [a, b, expected_rest] = post_in_two(s, t, w, mid, h.floor, e);
        const auto rest_steps = slice(w.steps, mid, 1e300), rest_scans = slice(w.scans, mid, 1e300);
        EXPECT_EQ(stored_fixes(s, t), w.steps.size() + w.scans.size());
        const json latest = b["latest"];
        EXPECT_NEAR(latest["x"].get<double>(), expected_rest.back()["x"].get<double>(), 1e-9);
        const double final_error = std::hypot(latest["x"].get<double>() - w.end.x, latest["y"].get<double>() - w.end.y);
        EXPECT_LT(final_error, 1.5) << latest.dump();
        ::testing::Test::RecordProperty(std::string(c.fusion) + "_final_error_m", std::to_string(final_error));
        // A retry of the last request moves nothing: every input is at or before the last fused t.
        const json retry = body_of(call(s, "POST", t.path("/steps"), t.token, body(rest_steps, rest_scans).dump()));
        EXPECT_TRUE(retry["fused"].empty()) << retry.dump();
        EXPECT_EQ(stored_fixes(s, t), w.steps.size() + w.scans.size());
    }
}

// "kalman_seed", kalman_trilateration's name before the rename, is still taken: the track is a
// kalman_trilateration track (its options, its fused fixes, client-lib's trilateration filter),
// named by its new name in every answer, also once the server reads it back from the database.
TEST(ServerTracksRanging, TheDeprecatedNameKalmanSeedOpensAKalmanTrilaterationTrack) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    add_transmitters(s, h.floor);
    const json options = {{"r_sigma_m", 2.0}};
    const json opened = body_of(call(s, "POST", "/v1/tracks", "",
                                     json{{"map_id", h.map}, {"fusion", "kalman_seed"}, {"fusion_options", options}}.dump()),
                                201);
    EXPECT_EQ(opened["fusion"], "kalman_trilateration");
    EXPECT_EQ(opened["fusion_options"], options);
    // kalman_ranging's options are not kalman_trilateration's: refused under the new name.
    const Response refused = call(s, "POST", "/v1/tracks", "",
                                  json{{"map_id", h.map}, {"fusion", "kalman_seed"}, {"fusion_options", {{"r_floor_m", 1.0}}}}.dump());
    EXPECT_EQ(refused.status, 422) << refused.raw;
    EXPECT_NE(refused.body["error"]["message"].get<std::string>().find("not an option of kalman_trilateration"), std::string::npos)
        << refused.raw;

    const Track t{opened.at("id").get<std::int64_t>(), opened.at("token").get<std::string>()};
    const Walk w = make_walk(std::floor(unix_now()) - 60);
    auto config = fusion::trilateration_kalman_config();
    config.fixed_r_sigma_m = 2.0;
    Expected e{config, false, std::nullopt};
    post_in_two(s, t, w, w.t0 + 12.2, h.floor, e);

    s.stop();
    s.start();
    const json info = body_of(call(s, "GET", t.path(), t.token));
    EXPECT_EQ(info["fusion"], "kalman_trilateration");
    EXPECT_EQ(info["fusion_options"], options);
}

// The mean distance of a track's fused fixes at the walk's steps from the truth there.
static double mean_step_error(const json& fused, const Walk& w) {
    double sum = 0;
    std::size_t n = 0;
    for (const auto& f : fused)
        for (const auto& [t, at] : w.truth)
            if (f["t"].get<double>() == t) {
                sum += std::hypot(f["x"].get<double>() - at.x, f["y"].get<double>() - at.y);
                ++n;
            }
    EXPECT_EQ(n, w.truth.size());
    return n ? sum / static_cast<double>(n) : 0.0;
}

// ekf_ranging in two requests: the server's fused fixes are client-lib's RangingEkf on the same
// readings and steps (to 1e-9), with the track's options over the defaults, end near the truth,
// and a retry moves nothing. On this walk it is compared with kalman_ranging (within centimetres).
TEST(ServerTracksRanging, EkfTrackFusesReadingsAsClientLibDoes) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    add_transmitters(s, h.floor);
    const Walk w = make_walk(std::floor(unix_now()) - 60);
    const double mid = w.t0 + 12.2;
    // This walker's steps are made when stamped (no lead), its shadowing is ±2 dB.
    const json options = {{"step_lead_s", 0.0}, {"reading_sigma_db", 3.0}};
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion", "ekf_ranging"}, {"fusion_options", options}});
    const json info = body_of(call(s, "GET", t.path(), t.token));
    EXPECT_EQ(info["fusion"], "ekf_ranging");
    EXPECT_EQ(info["fusion_options"], options);
    ExpectedEkf e;
    e.config.step_lead_s = 0.0;
    e.config.reading_sigma_db = 3.0;
    json all = json::array();
    const auto [a, b, expected_rest] = post_in_two(s, t, w, mid, h.floor, e);
    const auto rest_steps = slice(w.steps, mid, 1e300), rest_scans = slice(w.scans, mid, 1e300);
    for (const auto& f : a["fused"]) all.push_back(f);
    for (const auto& f : b["fused"]) all.push_back(f);
    EXPECT_EQ(stored_fixes(s, t), w.steps.size() + w.scans.size());
    const json latest = b["latest"];
    const double final_error = std::hypot(latest["x"].get<double>() - w.end.x, latest["y"].get<double>() - w.end.y);
    EXPECT_LT(final_error, 1.0) << latest.dump();
    const json retry = body_of(call(s, "POST", t.path("/steps"), t.token, body(rest_steps, rest_scans).dump()));
    EXPECT_TRUE(retry["fused"].empty()) << retry.dump();
    EXPECT_EQ(stored_fixes(s, t), w.steps.size() + w.scans.size());

    // Against kalman_ranging (its defaults) on the same inputs in one request, ekf_ranging with
    // its defaults but for the step lead (this walker makes a step when it stamps it).
    const Track k = open_track(s, {{"map_id", h.map}, {"fusion", "kalman_ranging"}});
    const json kb = body_of(call(s, "POST", k.path("/steps"), k.token, body(w.steps, w.scans).dump()));
    const Track d =
        open_track(s, {{"map_id", h.map}, {"fusion", "ekf_ranging"}, {"fusion_options", {{"step_lead_s", 0.0}}}});
    const json db = body_of(call(s, "POST", d.path("/steps"), d.token, body(w.steps, w.scans).dump()));
    const double ekf_mean = mean_step_error(all, w), default_mean = mean_step_error(db["fused"], w);
    const double kalman_mean = mean_step_error(kb["fused"], w);
    ::testing::Test::RecordProperty("ekf_ranging_mean_error_m", std::to_string(default_mean));
    ::testing::Test::RecordProperty("ekf_ranging_sigma3_mean_error_m", std::to_string(ekf_mean));
    ::testing::Test::RecordProperty("kalman_ranging_mean_error_m", std::to_string(kalman_mean));
    std::printf("mean error at the steps: ekf_ranging %.3f m (reading σ 3 dB: %.3f m), kalman_ranging %.3f m\n", default_mean,
                ekf_mean, kalman_mean);
    // Not a ranking: on this short walk with exact steps and a smooth ±2 dB shadowing they are
    // within a few centimetres of each other (0.29, 0.34 and 0.31 m when written); the
    // Kalman-fusion paper's simulated walks rank them (docs/transmitters.md).
    EXPECT_LT(default_mean, 0.6);
    EXPECT_LT(ekf_mean, 0.6);
    EXPECT_LT(default_mean, kalman_mean + 0.15);
}

// ekf_ranging takes a posted fix as a position update (its accuracy_m as R, floored at 0.5 m),
// starts at one, and, once running, takes a scan hearing two known transmitters (or none) as
// readings: RangingEkf in-process on the same inputs.
TEST(ServerTracksRanging, EkfTakesPostedFixesAndScansHearingFewTransmitters) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    add_transmitters(s, h.floor);
    const Walk w = make_walk(std::floor(unix_now()) - 60);
    const Track t = open_track(s, {{"map_id", h.map}, {"fusion", "ekf_ranging"}});
    json two = w.scans[1];
    two["readings"] = json::array({w.scans[1]["readings"][0], w.scans[1]["readings"][2]});
    json none = w.scans[2];
    none["readings"] = json::array({{{"type", "wifi"}, {"bssid", "bb:00:00:00:00:09"}, {"rss", -50.0}}});
    const json fix0 = {{"t", w.t0}, {"floor_id", h.floor}, {"x", 3.2}, {"y", 2.9}, {"accuracy_m", 1.5}};
    const json fix1 = {{"t", w.t0 + 4.2}, {"floor_id", h.floor}, {"x", 5.5}, {"y", 3.0}, {"accuracy_m", 0.1}};
    json req = body(slice(w.steps, w.t0, w.t0 + 6), {two, none});
    req["fixes"] = {fix0, fix1};
    const json got = body_of(call(s, "POST", t.path("/steps"), t.token, req.dump()));
    EXPECT_EQ(got["scan_fixes"].size(), 0u) << got.dump();  // neither scan could be ranged alone

    ExpectedEkf e;
    e.start({3.2, 2.9}, 1.5);
    std::vector<json> expected{e.fused(w.t0)};
    for (const auto& st : slice(w.steps, w.t0, w.t0 + 6)) {
        const double ts = st["t"].get<double>();
        for (const json& sc : {two, none})
            if (sc["t"].get<double>() < ts && sc["t"].get<double>() > ts - 1) expected.push_back(e.scan(sc));
        if (fix1["t"].get<double>() < ts && fix1["t"].get<double>() > ts - 1) {
            e.ekf->update_position({5.5, 3.0}, Eigen::Matrix2d::Identity() * 0.25);
            expected.push_back(e.fused(fix1["t"].get<double>()));
        }
        expected.push_back(e.step(st));
    }
    expect_same(got["fused"], expected);
    // The scan of two moved the filter; the one hearing none left it where it was.
    std::size_t i_two = 0;
    for (std::size_t i = 0; i < expected.size(); ++i)
        if (expected[i]["t"] == two["t"]) i_two = i;
    ASSERT_GT(i_two, 0u);
    EXPECT_GT(std::hypot(got["fused"][i_two]["x"].get<double>() - got["fused"][i_two - 1]["x"].get<double>(),
                         got["fused"][i_two]["y"].get<double>() - got["fused"][i_two - 1]["y"].get<double>()),
              1e-3);
}

// A radio fix posted directly (not a scan): kalman_ranging takes its accuracy_m as an isotropic
// covariance under the track's r_floor_m and r_scale; kalman_trilateration its fixed R.
TEST(ServerTracksRanging, DirectRadioFixesTakeTheirAccuracyOrTheFixedR) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);  // no transmitters: no scan, fixes only
    const double t0 = std::floor(unix_now()) - 60;
    for (const char* method : {"kalman_ranging", "kalman_trilateration"}) {
        SCOPED_TRACE(method);
        const bool trilateration = std::string(method) == "kalman_trilateration";
        const json options = trilateration ? json{{"q_sigma_per_m", 0.1}} : json{{"r_floor_m", 0.8}, {"r_scale", 2.0}};
        const Track t = open_track(s, {{"map_id", h.map}, {"fusion", method}, {"fusion_options", options}});
        const json req = {{"fixes", {{{"t", t0}, {"floor_id", h.floor}, {"x", 3.0}, {"y", 4.0}, {"accuracy_m", 1.5}},
                                     {{"t", t0 + 2.5}, {"floor_id", h.floor}, {"x", 5.0}, {"y", 4.5}, {"accuracy_m", 3.0}}}},
                          {"steps", {{{"t", t0 + 1}, {"length_m", 0.8}, {"heading_deg", 90.0}},
                                     {{"t", t0 + 2}, {"length_m", 0.8}, {"heading_deg", 90.0}}}}};
        const json got = body_of(call(s, "POST", t.path("/steps"), t.token, req.dump()));
        auto config = trilateration ? fusion::trilateration_kalman_config() : fusion::ranging_kalman_config();
        if (trilateration) config.kalman.step_sigma_per_m = 0.1;
        else config.r_floor_m = 0.8, config.r_scale = 2.0;
        const auto r_of = [&](double accuracy) {
            ranging::Fix f;
            f.sxx = f.syy = accuracy * accuracy;
            return fusion::ranging_measurement_noise(f, config);
        };
        fusion::KalmanConfig c = config.kalman;
        c.initial_sigma_m = std::sqrt(r_of(1.5).trace() / 2.0);
        fusion::KalmanFilter kf({3.0, 4.0}, c);
        std::vector<Point> expected{kf.position()};
        kf.predict({0.8, 0.0});
        expected.push_back(kf.position());
        kf.predict({0.8, 0.0});
        expected.push_back(kf.position());
        kf.update({5.0, 4.5}, r_of(3.0));
        expected.push_back(kf.position());
        ASSERT_EQ(got["fused"].size(), expected.size()) << got.dump();
        for (std::size_t i = 0; i < expected.size(); ++i) {
            EXPECT_NEAR(got["fused"][i]["x"].get<double>(), expected[i].x, 1e-9) << i;
            EXPECT_NEAR(got["fused"][i]["y"].get<double>(), expected[i].y, 1e-9) << i;
        }
        EXPECT_NEAR(got["fused"][3]["accuracy_m"].get<double>(), std::sqrt(kf.covariance().trace() / 2.0), 1e-9);
    }
}

TEST(ServerTracksRanging, BadInputIsRefusedAndWritesNothing) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    add_transmitters(s, h.floor);
    const Track first = open_track(s, {{"map_id", h.map}, {"fusion", "kalman_ranging"}});
    // Unknown fusion, and fusion_options that are not the method's, or out of range, or not numbers.
    const std::vector<std::pair<json, std::string>> bad = {
        {{{"fusion", "kalman"}}, "fusion"},
        {{{"fusion", "walk_pf"}, {"fusion_options", {{"q_sigma_m", 0.3}}}}, "fusion_options"},
        {{{"fusion_options", {{"q_sigma_m", 0.3}}}}, "fusion_options"},  // the default, walk_pf
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", json::array()}}, "fusion_options"},
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", {{"r_floor_m", 1.0}}}}, "fusion_options.r_floor_m"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"r_sigma_m", 1.0}}}}, "fusion_options.r_sigma_m"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"sigma", 1.0}}}}, "fusion_options.sigma"},
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", {{"r_sigma_m", 0.0}}}}, "fusion_options.r_sigma_m"},
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", {{"r_sigma_m", -2.0}}}}, "fusion_options.r_sigma_m"},
        {{{"fusion", "kalman_trilateration"}, {"fusion_options", {{"q_sigma_m", 1e6}}}}, "fusion_options.q_sigma_m"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"r_scale", "2"}}}}, "fusion_options.r_scale"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"q_sigma_per_m", nullptr}}}}, "fusion_options.q_sigma_per_m"},
        {{{"fusion", "kalman_ranging"}, {"fusion_options", {{"reading_sigma_db", 3.0}}}}, "fusion_options.reading_sigma_db"},
        {{{"fusion", "ekf_ranging"}, {"fusion_options", {{"r_floor_m", 1.0}}}}, "fusion_options.r_floor_m"},
        {{{"fusion", "ekf_ranging"}, {"fusion_options", {{"reading_sigma_db", 0.0}}}}, "fusion_options.reading_sigma_db"},
        {{{"fusion", "ekf_ranging"}, {"fusion_options", {{"step_lead_s", -0.5}}}}, "fusion_options.step_lead_s"},
        {{{"fusion", "ekf_ranging"}, {"fusion_options", {{"huber_k", "2"}}}}, "fusion_options.huber_k"},
        {{{"fusion", "ekf_ranging"}, {"fusion_options", {{"offset_sigma_db", 1e9}}}}, "fusion_options.offset_sigma_db"},
    };
    for (const auto& [fields, name] : bad) {
        json req = fields;
        req["map_id"] = h.map;
        const Response r = call(s, "POST", "/v1/tracks", "", req.dump());
        EXPECT_GE(r.status, 400) << req.dump();
        EXPECT_LT(r.status, 500) << req.dump();
        EXPECT_NE(r.body["error"]["message"].get<std::string>().find(name), std::string::npos) << r.raw;
    }
    // Nothing was written: the next track takes the next id.
    const Track next = open_track(s, {{"map_id", h.map}, {"fusion", "kalman_trilateration"}});
    EXPECT_EQ(next.id, first.id + 1);
    const Track ekf = open_track(s, {{"map_id", h.map}, {"fusion", "ekf_ranging"}});

    // A scan that hears two known transmitters (and an unknown one), alone or after good
    // input in the same request: 422 with the count, nothing stored, the filter not moved.
    const Walk w = make_walk(std::floor(unix_now()) - 60);
    json two = w.scans[1];
    two["readings"] = json::array({w.scans[1]["readings"][0], w.scans[1]["readings"][2],
                                   {{"type", "wifi"}, {"bssid", "bb:00:00:00:00:09"}, {"rss", -50.0}}});
    for (const Track& t : {first, next}) {
        for (const json& req : {body({}, {two}), body(slice(w.steps, w.t0, w.t0 + 3), {w.scans[0], two})}) {
            const Response r = call(s, "POST", t.path("/steps"), t.token, req.dump());
            EXPECT_EQ(r.status, 422) << r.raw;
            EXPECT_EQ(r.body["error"]["code"], "too_few_transmitters") << r.raw;
            const std::string message = r.body["error"]["message"].get<std::string>();
            EXPECT_NE(message.find("hears 2 known transmitters"), std::string::npos) << message;
            EXPECT_NE(message.find("scans["), std::string::npos) << message;
            EXPECT_EQ(stored_fixes(s, t), 0u);
        }
        // The filter never started: the good scan alone now starts it.
        const json ok = body_of(call(s, "POST", t.path("/steps"), t.token, body({}, {w.scans[0]}).dump()));
        EXPECT_EQ(ok["stored"], 1);
    }

    // ekf_ranging refuses such a scan only before it runs (it starts at a ranged one); after a
    // ranged scan in the same request it takes its two readings.
    {
        const Response r = call(s, "POST", ekf.path("/steps"), ekf.token, body({}, {two}).dump());
        EXPECT_EQ(r.status, 422) << r.raw;
        EXPECT_EQ(r.body["error"]["code"], "too_few_transmitters") << r.raw;
        const std::string message = r.body["error"]["message"].get<std::string>();
        EXPECT_NE(message.find("hears 2 known transmitters"), std::string::npos) << message;
        EXPECT_NE(message.find("ekf_ranging starts at a ranged scan"), std::string::npos) << message;
        EXPECT_EQ(stored_fixes(s, ekf), 0u);
        // A step first.
        EXPECT_EQ(call(s, "POST", ekf.path("/steps"), ekf.token, body({w.steps[0]}, {}).dump()).status, 422);
        const json ok = body_of(call(s, "POST", ekf.path("/steps"), ekf.token,
                                     body(slice(w.steps, w.t0, w.t0 + 3), {w.scans[0], two}).dump()));
        EXPECT_EQ(ok["stored"], 4) << ok.dump();
        EXPECT_EQ(ok["scan_fixes"].size(), 1u) << ok.dump();  // the scan of two gave readings, no fix
    }

    // A map whose floor has no transmitters: every scan hears none.
    const auto bare = locus::testing::make_hierarchy(s, "Bare");
    const Track lonely = open_track(s, {{"map_id", bare.map}, {"fusion", "kalman_trilateration"}});
    const Response r = call(s, "POST", lonely.path("/steps"), lonely.token, body({}, {w.scans[0]}).dump());
    EXPECT_EQ(r.status, 422) << r.raw;
    EXPECT_EQ(r.body["error"]["code"], "too_few_transmitters") << r.raw;
    EXPECT_NE(r.body["error"]["message"].get<std::string>().find("hears 0 known transmitters"), std::string::npos) << r.raw;
    EXPECT_EQ(stored_fixes(s, lonely), 0u);
    // A step before any fix cannot be fused.
    EXPECT_EQ(call(s, "POST", lonely.path("/steps"), lonely.token, body({w.steps[0]}, {}).dump()).status, 422);
}

// A server that does not hold the track's filter (here: restarted) starts it again at the
// track's latest stored fix, as sure as the filter was then, and keeps the track's fusion and
// options.
TEST(ServerTracksRanging, ARestartResumesAtTheLatestStoredFix) {
    ServerProcess s({"--quiet"});
    const json options = {{"r_floor_m", 0.7}, {"q_sigma_per_m", 0.4}};
    const HalfWalked hw = walk_half(s, "kalman_ranging", options, 8.2);
    const json latest = restart(s, hw, "kalman_ranging", options);
    const auto rest_steps = slice(hw.w.steps, latest["t"].get<double>() - 2.5, 1e300);  // the first ones were run: skipped
    const auto rest_scans = slice(hw.w.scans, hw.mid, 1e300);
    const json got = body_of(call(s, "POST", hw.t.path("/steps"), hw.t.token, body(rest_steps, rest_scans).dump()));

    auto config = fusion::ranging_kalman_config();
    config.r_floor_m = 0.7;
    config.kalman.step_sigma_per_m = 0.4;
    Expected e{config, true, std::nullopt};
    e.resume(latest);
    expect_same(got["fused"], e.run(slice(rest_steps, hw.mid, 1e300), rest_scans));
    EXPECT_EQ(got["fused"][0]["floor_id"], hw.h.floor);
}

// ekf_ranging after a restart: resumed at the latest stored fix (σ its accuracy_m, the offset
// and heading bias afresh) with the floor's transmitters as anchors, even when the first
// request after it holds steps alone; then scans' readings update it as before.
TEST(ServerTracksRanging, ARestartResumesAnEkfTrackAtTheLatestStoredFix) {
    ServerProcess s({"--quiet"});
    const json options = {{"q_sigma_per_m", 0.2}, {"huber_k", 2.0}};
    const HalfWalked hw = walk_half(s, "ekf_ranging", options, 8.2);
    const json latest = restart(s, hw, "ekf_ranging", options);
    ExpectedEkf e;
    e.config.step_sigma_per_m = 0.2;
    e.config.huber_k = 2.0;
    e.resume(latest);
    // Steps alone first (the earliest were run before the restart: skipped), then the rest.
    const auto more_steps = slice(hw.w.steps, latest["t"].get<double>() - 2.5, hw.mid + 3);
    const json got_steps = body_of(call(s, "POST", hw.t.path("/steps"), hw.t.token, body(more_steps, {}).dump()));
    expect_same(got_steps["fused"], e.run(slice(more_steps, hw.mid, 1e300), {}));
    const auto rest_steps = slice(hw.w.steps, hw.mid + 3, 1e300), rest_scans = slice(hw.w.scans, hw.mid + 3, 1e300);
    const json got = body_of(call(s, "POST", hw.t.path("/steps"), hw.t.token, body(rest_steps, rest_scans).dump()));
    const auto expected = e.run(rest_steps, rest_scans);
    expect_same(got["fused"], expected);
    EXPECT_EQ(got["fused"][0]["floor_id"], hw.h.floor);
    EXPECT_LT(std::hypot(expected.back()["x"].get<double>() - hw.w.end.x, expected.back()["y"].get<double>() - hw.w.end.y), 1.5);
}

// Two servers sharing a PostgreSQL database: a Kalman track's requests alternate between them,
// and the one that did not run the last request resumes at the latest stored fix, ranging its
// scans on the transmitters the other server created.
TEST(ServerTracksRanging, AnotherServerSharingTheDatabaseResumesTheTrack) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
    ServerProcess a({"--quiet"});
    ServerProcess b({"--quiet"}, locus::testing::SameDatabase{a.db()});
    const HalfWalked hw = walk_half(a, "kalman_trilateration", nullptr, 10.2);
    const auto [latest, got] = finish_on(b, hw);
    Expected e{fusion::trilateration_kalman_config(), false, std::nullopt};
    e.resume(latest);
    expect_same(got["fused"], e.run(slice(hw.w.steps, hw.mid, 1e300), slice(hw.w.scans, hw.mid, 1e300)));
    EXPECT_EQ(stored_fixes(a, hw.t), hw.w.steps.size() + hw.w.scans.size());
}

// ekf_ranging across two servers sharing a PostgreSQL database: the second resumes at the
// latest stored fix the first wrote, its anchors the transmitters the first created.
TEST(ServerTracksRanging, AnotherServerSharingTheDatabaseResumesAnEkfTrack) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
    ServerProcess a({"--quiet"});
    ServerProcess b({"--quiet"}, locus::testing::SameDatabase{a.db()});
    const HalfWalked hw = walk_half(a, "ekf_ranging", {{"step_lead_s", 0.0}}, 10.2);
    const auto [latest, got] = finish_on(b, hw);
    ExpectedEkf e;
    e.config.step_lead_s = 0.0;
    e.resume(latest);
    expect_same(got["fused"], e.run(slice(hw.w.steps, hw.mid, 1e300), slice(hw.w.scans, hw.mid, 1e300)));
    EXPECT_EQ(stored_fixes(a, hw.t), hw.w.steps.size() + hw.w.scans.size());
}

}  // namespace
}  // namespace server_tracks_ranging_test
