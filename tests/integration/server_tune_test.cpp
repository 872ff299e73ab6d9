// POST /v1/radiomaps/{id}/tune over HTTP: the CV table, the chosen settings stored and shown
// by GET /v1/radiomaps/{id}, localize answers following them (and surviving a restart), and
// every refusal: unknown id, too few RPs, bad bodies, a second tune while one runs.
#include <gtest/gtest.h>

#include <cmath>
#include <future>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_tune_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

std::string ap(int i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "aa:00:00:00:%02x:%02x", i / 256, i % 256);
    return buf;
}

// Log-distance path loss from `aps` transmitters spread over a w × h floor, with a fixed
// per-(RP, AP) wobble so neighbouring RPs are not exact interpolations of each other.
double rss_at(double x, double y, int a, double w, double h) {
    const double ax = w * std::fmod(0.37 * a + 0.11, 1.0), ay = h * std::fmod(0.61 * a + 0.29, 1.0);
    const double d = std::hypot(x - ax, y - ay) + 1.0;
    const double wobble = 3.0 * std::sin(1.7 * x + 2.3 * y + 0.9 * a);
    return std::clamp(-35.0 - 25.0 * std::log10(d) + wobble, -99.0, -20.0);
}

// A radio map of nx × ny RPs, `spacing` metres apart, each hearing every AP.
json grid_map(int nx, int ny, double spacing, int aps) {
    json rps = json::array();
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            const double x = spacing * i, y = spacing * j;
            json ms = json::array();
            for (int a = 0; a < aps; ++a)
                ms.push_back({{"bssid", ap(a)}, {"mean", rss_at(x, y, a, spacing * nx, spacing * ny)},
                              {"variance", 4.0}, {"count", 1}});
            rps.push_back({{"name", "rp" + std::to_string(i) + "_" + std::to_string(j)}, {"x", x}, {"y", y},
                           {"scans", 1}, {"measurements", ms}});
        }
    return {{"name", "grid"}, {"rps", rps}};
}

json scan_at(double x, double y, int aps, double w, double h) {
    json readings = json::array();
    for (int a = 0; a < aps; ++a) readings.push_back({{"bssid", ap(a)}, {"rss", rss_at(x + 0.4, y + 0.7, a, w, h)}});
    return {{"scans", json::array({readings})}};
}

struct Tune : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t import(const json& doc) {
        const auto r = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc);
        EXPECT_EQ(r.status, 201) << r.raw;
        return r.body.at("id").get<std::int64_t>();
    }
    static std::string path(std::int64_t rm, const char* tail) { return "/v1/radiomaps/" + std::to_string(rm) + tail; }
};

TEST_F(Tune, StoresTheLowestErrorSettingAndLocalizeFollowsItAcrossARestart) {
    constexpr int nx = 8, ny = 6, aps = 6;
    constexpr double spacing = 3.0;
    const auto rm = import(grid_map(nx, ny, spacing, aps));

    const auto before = body_of(s.get(path(rm, "")));
    EXPECT_EQ(before.at("settings").at("source"), "built-in");
    EXPECT_EQ(before.at("settings").at("algorithm"), "bayes");
    EXPECT_FALSE(before.contains("tune"));

    std::vector<json> queries;
    for (double x : {1.0, 7.5, 13.0, 19.0})
        for (double y : {2.0, 9.5}) queries.push_back(scan_at(x, y, aps, spacing * nx, spacing * ny));
    std::vector<json> untuned;
    for (const auto& q : queries) untuned.push_back(body_of(s.post(path(rm, "/localize"), q)));

    const auto tuned = body_of(s.post_raw(path(rm, "/tune"), ""));
    const auto& table = tuned.at("tune");
    EXPECT_EQ(table.at("rps"), nx * ny);
    EXPECT_EQ(table.at("queries"), nx * ny);  // every RP held out once
    EXPECT_EQ(table.at("folds"), 10);
    const auto& rows = table.at("candidates");
    ASSERT_GE(rows.size(), 5u);
    const auto chosen = table.at("chosen").get<std::size_t>();
    for (const auto& row : rows) {
        EXPECT_LE(rows.at(chosen).at("mean_error_m").get<double>(), row.at("mean_error_m").get<double>());
        EXPECT_GT(row.at("mean_error_m").get<double>(), 0.0);  // RPs are held out: no zero error
    }
    const json settings = rows.at(chosen).at("settings");
    EXPECT_EQ(tuned.at("settings").at("algorithm"), settings.at("algorithm"));
    EXPECT_EQ(tuned.at("settings").at("options"), settings.at("options"));
    // This map is made so that the built-in bayes is not the best: the answers must change.
    EXPECT_NE(chosen, 0u) << table.dump();

    const auto shown = body_of(s.get(path(rm, "")));
    EXPECT_EQ(shown.at("settings").at("source"), "tuned");
    EXPECT_EQ(shown.at("settings").at("algorithm"), settings.at("algorithm"));
    EXPECT_EQ(shown.at("tune"), table);

    // A request naming nothing now gets exactly what naming the chosen setting gets.
    auto check_follows = [&] {
        bool changed = false;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            const auto plain = body_of(s.post(path(rm, "/localize"), queries[i]));
            json named = queries[i];
            named["algorithm"] = settings.at("algorithm");
            named["options"] = settings.at("options");
            const auto explicit_answer = body_of(s.post(path(rm, "/localize"), named));
            EXPECT_EQ(plain.at("algorithm"), settings.at("algorithm"));
            EXPECT_EQ(plain.at("x"), explicit_answer.at("x"));
            EXPECT_EQ(plain.at("y"), explicit_answer.at("y"));
            changed = changed || plain.at("x") != untuned[i].at("x") || plain.at("y") != untuned[i].at("y");
        }
        EXPECT_TRUE(changed) << "no answer moved after the tune";
    };
    check_follows();

    // A request naming the built-in algorithm gets it with its built-in options.
    json bayes = queries[0];
    bayes["algorithm"] = "bayes";
    EXPECT_EQ(body_of(s.post(path(rm, "/localize"), bayes)).at("x"), untuned[0].at("x"));

    s.stop();
    s.start();
    EXPECT_EQ(body_of(s.get(path(rm, ""))).at("settings").at("algorithm"), settings.at("algorithm"));
    check_follows();
}

TEST_F(Tune, AMapsIndexTakesItsRadioMapsSettingsOnlyWhenTheyAgree) {
    const auto rm = import(grid_map(8, 6, 3.0, 6));
    body_of(s.post_raw(path(rm, "/tune"), ""));
    const auto settings = body_of(s.get(path(rm, ""))).at("settings");
    const auto q = scan_at(7.5, 9.5, 6, 24.0, 18.0);
    const std::string map_path = "/v1/maps/" + std::to_string(h.map) + "/localize";
    EXPECT_EQ(body_of(s.post(map_path, q)).at("algorithm"), settings.at("algorithm"));

    // A second radio map with no settings of its own: they no longer agree.
    json other = grid_map(2, 2, 3.0, 6);
    other["name"] = "other";
    import(other);
    EXPECT_EQ(body_of(s.post(map_path, q)).at("algorithm"), "bayes");
}

TEST_F(Tune, RefusesWhatCannotBeTuned) {
    const auto missing = s.post_raw("/v1/radiomaps/999999/tune", "");
    EXPECT_EQ(missing.status, 404) << missing.raw;
    EXPECT_EQ(missing.body.at("error").at("code"), "not_found");

    const auto empty = s.post_raw(path(h.radiomap, "/tune"), "");
    EXPECT_EQ(empty.status, 422) << empty.raw;
    EXPECT_EQ(empty.body.at("error").at("code"), "cannot_tune");
    EXPECT_NE(empty.body.at("error").at("message").get<std::string>().find("at least 2 RPs"), std::string::npos);

    locus::testing::make_rp(s, h.radiomap, "only", 1, 1);
    const auto one = s.post_raw(path(h.radiomap, "/tune"), "");
    EXPECT_EQ(one.status, 422) << one.raw;
    EXPECT_NE(one.body.at("error").at("message").get<std::string>().find("it has 1"), std::string::npos);
    EXPECT_EQ(body_of(s.get(path(h.radiomap, ""))).at("settings").at("source"), "built-in");  // nothing written

    const auto rm = import(grid_map(3, 3, 3.0, 4));
    const auto bad = [&](const std::string& body, int status, const char* code) {
        const auto r = s.post_raw(path(rm, "/tune"), body);
        EXPECT_EQ(r.status, status) << body << " -> " << r.raw;
        EXPECT_EQ(r.body.at("error").at("code"), code) << body;
    };
    bad("{", 400, "invalid_json");
    bad("[]", 400, "invalid_json");
    bad(R"({"folds": 1})", 422, "out_of_range");
    bad(R"({"folds": "ten"})", 422, "invalid_field");
    bad(R"({"max_queries": 100000})", 422, "out_of_range");
    bad(R"({"fold": 5})", 422, "invalid_field");
    EXPECT_EQ(body_of(s.get(path(rm, ""))).at("settings").at("source"), "built-in");
    EXPECT_EQ(body_of(s.post(path(rm, "/tune"), {{"folds", 3}})).at("tune").at("folds"), 3);
}

TEST_F(Tune, ASecondTuneOfTheSameRadioMapWhileOneRunsIsAConflict) {
    // Big enough that a tune outlasts the three requests' start by far (20 folds: 20 index builds,
    // 480 held-out RPs; a second in a Release build), small enough for the sanitized suite.
    const auto rm = import(grid_map(24, 20, 2.0, 30));
    std::vector<std::future<locus::testing::Response>> runs;
    for (int i = 0; i < 3; ++i)
        runs.push_back(std::async(std::launch::async, [&] { return s.post(path(rm, "/tune"), {{"folds", 20}}); }));
    int ok = 0, conflict = 0;
    for (auto& f : runs) {
        const auto r = f.get();
        if (r.status == 200) ++ok;
        else if (r.status == 409 && r.body.at("error").at("code") == "tune_running") ++conflict;
        else ADD_FAILURE() << r.status << " " << r.raw;
    }
    EXPECT_GE(ok, 1);
    EXPECT_GE(conflict, 1);
}

TEST_F(Tune, TheCliTunesAndPrintsTheTableOrSaysWhyNot) {
    const auto rm = import(grid_map(4, 4, 3.0, 5));
    const auto r = locus::testing::run_command(
        {LOCUS_CLI_BIN, "tune", "--server", s.url(), "--radiomap", std::to_string(rm), "--folds", "4"});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("16 RPs, 4-fold CV"), std::string::npos) << r.out;
    const auto shown = body_of(s.get(path(rm, "")));
    EXPECT_NE(r.out.find("stored: " + shown.at("settings").at("algorithm").get<std::string>()), std::string::npos) << r.out;
    EXPECT_EQ(shown.at("tune").at("folds"), 4);

    const auto refused = locus::testing::run_command(
        {LOCUS_CLI_BIN, "tune", "--server", s.url(), "--radiomap", std::to_string(h.radiomap)});
    EXPECT_NE(refused.status, 0);
    EXPECT_NE(refused.err.find("at least 2 RPs"), std::string::npos) << refused.err;
}

TEST_F(Tune, ATuneWhileRpsAreWrittenWorksOnOneSnapshot) {
    const auto rm = import(grid_map(30, 20, 2.0, 20));
    auto tune = std::async(std::launch::async, [&] { return s.post(path(rm, "/tune"), {{"folds", 50}}); });
    int added = 0;
    for (int i = 0; i < 3; ++i) {
        const auto rp = locus::testing::make_rp(s, rm, "late" + std::to_string(i), 1.0 + i, 41.0);
        json scan = json::array();
        for (int a = 0; a < 20; ++a) scan.push_back({{"bssid", ap(a)}, {"rss", -60.0 - a}});
        body_of(s.post("/v1/rps/" + std::to_string(rp) + "/scans", {{"scans", json::array({scan})}}));
        ++added;
    }
    const auto table = body_of(tune.get()).at("tune");
    // The RPs as one transaction saw them: 600, plus the late ones committed before it began
    // (an RP is created empty, so it is no query until its scans are in).
    const auto rps = table.at("rps").get<int>(), queries = table.at("queries").get<int>();
    EXPECT_GE(rps, 600);
    EXPECT_LE(rps, 600 + added);
    EXPECT_GE(queries, 600);
    EXPECT_LE(queries, rps);
    EXPECT_EQ(body_of(s.get(path(rm, ""))).at("tune"), table);
}

}  // namespace
}  // namespace server_tune_test
