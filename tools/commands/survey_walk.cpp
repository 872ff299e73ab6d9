// `locus survey walk PATH... --radiomap FLOOR=ID... [--landmarks FILE.csv] [--cell M]`: a
// survey made by walking (docs/survey.md "Walking surveys"). PATH is a GetSensorData logfile
// (the IPIN competitions' format, datasets/ipin_log.hpp) or a folder of them. Each WiFi scan
// gets the position interpolated in time between the landmarks around it
// (locus/survey/walk.hpp): the logfile's POSI lines, turned into each floor's frame through
// the floor's georeference read from the server, or the landmarks CSV (t,floor,x,y in the
// floor's frame) for a logger without POSI lines. FLOOR is the floor number the landmarks use.
//
// Every file is read and checked before the first request; uploads carry
// "walk-<content hash>-<cell>" ids, so running it again merges nothing twice.
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "floor_geo_json.hpp"
#include "locus/geo/georeference.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"
#include "walk_survey.hpp"

namespace locus_cli_survey_walk {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
namespace fs = std::filesystem;

struct Args {
    ServerArgs server;
    std::vector<std::string> paths;
    std::vector<std::string> radiomaps;  // FLOOR=ID
    std::string landmarks;
    double cell = 5.0;
    int concurrency = 4;
    bool progress = true;
};

std::map<int, std::int64_t> parse_mapping(const std::vector<std::string>& items) {
    std::map<int, std::int64_t> out;
    for (const auto& s : items) {
        const auto eq = s.find('=');
        try {
            if (eq == std::string::npos) throw std::invalid_argument("no '='");
            std::size_t used = 0;
            const int floor = std::stoi(s.substr(0, eq), &used);
            if (used != eq) throw std::invalid_argument("floor");
            const std::string id_text = s.substr(eq + 1);
            const long long id = std::stoll(id_text, &used);
            if (used != id_text.size() || id <= 0) throw std::invalid_argument("id");
            if (!out.emplace(floor, id).second) throw CommandError("--radiomap names floor " + std::to_string(floor) + " twice");
        } catch (const std::logic_error&) {
            throw CommandError("--radiomap '" + s + "': expected FLOOR=ID, e.g. 0=12 or -2=14");
        }
    }
    return out;
}

std::vector<std::string> logfiles(const std::vector<std::string>& paths) {
    std::vector<std::string> out;
    for (const auto& p : paths) {
        std::error_code ec;
        if (fs::is_directory(p, ec)) {
            std::vector<std::string> in_dir;
            for (const auto& e : fs::directory_iterator(p))
                if (e.is_regular_file() && datasets::ipin::file_looks_like_log(e.path().string())) in_dir.push_back(e.path().string());
            if (in_dir.empty()) throw CommandError("folder '" + p + "' holds no GetSensorData logfile");
            std::sort(in_dir.begin(), in_dir.end());
            out.insert(out.end(), in_dir.begin(), in_dir.end());
        } else if (fs::is_regular_file(p, ec)) {
            out.push_back(p);
        } else {
            throw CommandError("'" + p + "' is neither a file nor a folder");
        }
    }
    return out;
}

void run(const Args& a) {
    const auto mapping = parse_mapping(a.radiomaps);
    const auto files = logfiles(a.paths);
    if (!a.landmarks.empty() && files.size() != 1)
        throw CommandError("--landmarks times are on one logfile's clock: give exactly one logfile with it");

    // The floors' georeferences, for POSI landmarks (lat/lon).
    const auto options = a.server.client_options();
    api::Client client(options);
    std::map<int, std::optional<geo::FloorToEarth>> frames;
    for (const auto& [floor, rm] : mapping) {
        const auto info = client.radiomap(rm);
        const auto ref = georeference_of(client.get("/v1/floors/" + std::to_string(info.floor_id)));
        auto& frame = frames[floor];
        if (ref) frame.emplace(*ref);
    }
    std::vector<Walk> walks;
    std::size_t dropped_total = 0;
    for (const auto& path : files) {
        const std::string bytes = read_file(path);
        datasets::ipin::Log log;
        try {
            log = datasets::ipin::parse_log(bytes, path);
        } catch (const datasets::ipin::LogError& e) {
            throw CommandError(std::string(e.what()) + "; nothing uploaded");
        }
        Walk w;
        w.source = path;
        w.stem = fs::path(path).stem().string();
        if (!a.landmarks.empty()) {
            const std::string csv = read_file(a.landmarks);
            try {
                w.landmarks = datasets::parse_landmarks_csv(csv, a.landmarks);
            } catch (const std::runtime_error& e) {
                throw CommandError(std::string(e.what()) + "; nothing uploaded");
            }
            w.content = fingerprint(bytes + "\n" + csv);
        } else {
            if (log.posi.empty()) throw CommandError(path + " has no POSI line: give the landmarks with --landmarks FILE.csv");
            std::size_t dropped = 0;
            w.landmarks = landmarks_of_posi(
                log,
                [&](int floor, double lat, double lon) -> std::optional<Point> {
                    const auto it = frames.find(floor);
                    if (it == frames.end()) return std::nullopt;
                    if (!it->second)
                        throw CommandError("floor " + std::to_string(floor) + " (radio map " + std::to_string(mapping.at(floor)) +
                                           ") has no georeference, so POSI lat/lon cannot be placed on it: set its geo "
                                           "(PATCH /v1/floors/{id}) or give --landmarks FILE.csv");
                    return it->second->to_floor({lat, lon});
                },
                dropped);
            dropped_total += dropped;
            w.content = fingerprint(bytes);
        }
        add_wifi_scans(log, w);
        walks.push_back(std::move(w));
    }
    WalkCounts counts;
    std::vector<RpJob> jobs;
    json per_file = json::array();
    for (const auto& w : walks) {
        WalkCounts one;
        try {
            auto j = walk_jobs(w, mapping, a.cell, one);
            for (auto& x : j) jobs.push_back(std::move(x));
            WalkCounts* acc = &counts;
            acc->scans += one.scans;
            acc->placed += one.placed;
            acc->before_first += one.before_first;
            acc->after_last += one.after_last;
            acc->floor_change += one.floor_change;
            acc->unmapped_floor += one.unmapped_floor;
            acc->rps += one.rps;
            for (const auto& [f, n] : one.rps_per_floor) acc->rps_per_floor[f] += n;
            for (const auto& [f, n] : one.scans_per_floor) acc->scans_per_floor[f] += n;
        } catch (const std::invalid_argument& e) {
            throw CommandError(w.source + ": " + e.what() + "; nothing uploaded");
        }
        json row = one.to_json();
        row["file"] = w.source;
        per_file.push_back(row);
    }
    UploadOptions uo;
    uo.concurrency = a.concurrency;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    json out = summary.to_json();
    out["cell_m"] = a.cell;
    out["walk"] = counts.to_json();
    out["landmarks_on_unmapped_floors"] = dropped_total;
    out["files"] = per_file;
    std::cout << out.dump() << "\n";
    for (const auto& f : summary.failures) std::cerr << "locus: " << f << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
}

}  // namespace

LOCUS_COMMAND("survey-walk", [](CLI::App& app) {
    auto& survey = locus::tools::group(app, "survey", "Plan reference points and upload survey scans");
    auto* w = survey.add_subcommand("walk", "Upload a survey made by walking between landmarks (GetSensorData logfiles; docs/survey.md)");
    auto a = std::make_shared<Args>();
    a->server.add_to(*w);
    w->add_option("--radiomap", a->radiomaps, "FLOOR=ID: the radio map of the landmarks' floor number FLOOR (repeat per floor)")
        ->required();
    w->add_option("--landmarks", a->landmarks, "CSV of t,floor,x,y (floor frame) instead of the logfile's POSI lines")
        ->check(CLI::ExistingFile);
    w->add_option("--cell", a->cell, "pool scans into RPs of this many metres along the path (0: one RP per scan)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    w->add_option("--concurrency", a->concurrency, "parallel connections")->capture_default_str()->check(CLI::Range(1, 64));
    locus::tools::add_no_progress_flag(*w, a->progress);
    w->add_option("PATH", a->paths, "logfiles, or folders of them")->required();
    w->callback([a] { run(*a); });
});

}  // namespace locus_cli_survey_walk
