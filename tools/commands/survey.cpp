// `locus survey plan` and `locus survey upload`: getting a radio map into the server from a
// walk with a phone (docs/spec.md §3). File formats: datasets/survey_format.hpp and docs/survey.md.
#include <unistd.h>

#include <iostream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/survey_format.hpp"
#include "survey_connect.hpp"
#include "survey_plan.hpp"
#include "survey_upload.hpp"

namespace locus_cli_survey {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;

struct PlanArgs {
    ServerArgs server;
    std::int64_t floor = 0;
    double cell = 2.0;
    std::int64_t radiomap = 0;
    bool create = false;
};

void plan_survey(const PlanArgs& a) {
    if (a.create && a.radiomap == 0) throw CommandError("--create needs --radiomap ID (the radio map to add the RPs to)");
    api::Client client(a.server.client_options());
    const auto floor = client.floor(a.floor);
    std::vector<Room> rooms;
    for (const auto& r : client.rooms(a.floor)) rooms.push_back({r.id, r.name, r.rects});
    survey_plan::Plan p;
    try {
        p = survey_plan::plan_grid(floor.width, floor.height, a.cell, rooms);
    } catch (const std::invalid_argument& e) {
        throw CommandError(e.what());
    }
    json points = json::array();
    for (const auto& pt : p.points) points.push_back({{"name", pt.name}, {"x", pt.at.x}, {"y", pt.at.y}});
    json out = {{"floor_id", floor.id},
                {"width", floor.width},
                {"height", floor.height},
                {"cell", a.cell},
                {"required_points", p.required},
                {"columns", p.columns},
                {"rows", p.rows},
                {"proposed", p.points.size()},
                {"outside_rooms", p.outside_rooms},
                {"points", points}};
    if (a.create) {
        const auto rm = client.radiomap(a.radiomap);
        if (rm.floor_id != floor.id)
            throw CommandError("radio map " + std::to_string(rm.id) + " belongs to floor " + std::to_string(rm.floor_id) +
                               ", not " + std::to_string(floor.id));
        std::map<std::string, std::int64_t> existing;
        for (const auto& rp : client.rps(rm.id)) existing[rp.name] = rp.id;
        std::size_t created = 0;
        for (const auto& pt : p.points) {
            if (existing.count(pt.name)) continue;
            client.create_rp(rm.id, pt.name, pt.at.x, pt.at.y);
            ++created;
        }
        out["radiomap_id"] = rm.id;
        out["created"] = created;
        out["already_present"] = p.points.size() - created;
    }
    std::cout << out.dump() << "\n";
}

struct UploadArgs {
    ServerArgs server;
    std::int64_t radiomap = 0;
    std::vector<std::string> files;
    std::string format = "auto";
    bool strict = false;
    int concurrency = 4;
    std::optional<std::size_t> stop_after;
    bool progress = true;
};

void upload(const UploadArgs& a) {
    const auto options = a.server.client_options();
    {
        api::Client client(options);
        client.radiomap(a.radiomap);  // fail early, with the server's message, on a wrong id
    }
    std::vector<RpJob> jobs;
    std::size_t malformed = 0, refused = 0;
    json files = json::array();
    for (const auto& path : a.files) {
        const std::string bytes = read_file(path);
        const auto format = a.format == "csv"     ? datasets::survey::Format::Csv
                            : a.format == "jsonl" ? datasets::survey::Format::JsonLines
                                                  : datasets::survey::format_of(path);
        auto parsed = datasets::survey::parse(bytes, format);
        for (const auto& e : parsed.errors) std::cerr << path << ":" << e.line << ": " << e.message << "\n";
        malformed += parsed.errors.size();
        const bool refuse = a.strict && !parsed.errors.empty();
        const std::string upload_id = "survey-" + fingerprint(bytes);
        files.push_back({{"file", path},
                         {"upload_id", upload_id},
                         {"rps", parsed.rps.size()},
                         {"scans", parsed.scans},
                         {"readings", parsed.readings},
                         {"malformed_lines", parsed.errors.size()},
                         {"refused", refuse}});
        if (refuse) {
            ++refused;
            continue;
        }
        for (auto& rp : parsed.rps) {
            RpJob job;
            job.radiomap_id = a.radiomap;
            job.name = rp.name;
            job.at = rp.at;
            job.scans = std::move(rp.scans);
            job.upload_id = upload_id;
            job.source = path;
            jobs.push_back(std::move(job));
        }
    }
    UploadOptions uo;
    uo.concurrency = a.concurrency;
    uo.stop_after = a.stop_after;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    json out = summary.to_json();
    out["radiomap_id"] = a.radiomap;
    out["files"] = files;
    out["malformed_lines"] = malformed;
    out["refused_files"] = refused;
    std::cout << out.dump() << "\n";
    for (const auto& f : summary.failures) std::cerr << "locus: " << f << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
    if (summary.interrupted) throw CommandError("stopped after " + std::to_string(*a.stop_after) + " RPs (--stop-after)", 3);
    if (refused > 0) throw CommandError(std::to_string(refused) + " file(s) refused by --strict: nothing of them was sent", 2);
}

}  // namespace

LOCUS_COMMAND("survey", [](CLI::App& app) {
    auto& survey = locus::tools::group(app, "survey", "Plan reference points and upload survey scans");

    auto* p = survey.add_subcommand("plan", "Propose an RP grid for a floor (ceil(area / cell^2) points), optionally create it");
    auto pa = std::make_shared<PlanArgs>();
    pa->server.add_to(*p);
    p->add_option("--floor", pa->floor, "floor id")->required();
    p->add_option("--cell", pa->cell, "grid cell side, metres")->capture_default_str()->check(CLI::PositiveNumber);
    p->add_option("--radiomap", pa->radiomap, "radio map to create the RPs in (with --create)");
    p->add_flag("--create", pa->create, "create the proposed RPs that do not exist yet");
    p->callback([pa] { plan_survey(*pa); });

    auto* u = survey.add_subcommand("upload", "Upload RP scans from JSON-lines or CSV files (see docs/survey.md)");
    auto ua = std::make_shared<UploadArgs>();
    ua->server.add_to(*u);
    u->add_option("--radiomap", ua->radiomap, "radio map id")->required();
    u->add_option("--format", ua->format, "auto (by extension: .csv or JSON lines), jsonl or csv")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "jsonl", "csv"}));
    u->add_flag("--strict", ua->strict, "refuse a whole file when any line of it is malformed");
    u->add_option("--concurrency", ua->concurrency, "parallel connections")->capture_default_str()->check(CLI::Range(1, 64));
    u->add_option("--stop-after", ua->stop_after, "upload only the first N RPs, then stop (to test resuming)")->group("");
    locus::tools::add_no_progress_flag(*u, ua->progress);
    u->add_option("FILE", ua->files, "survey files")->required()->check(CLI::ExistingFile);
    u->callback([ua] { upload(*ua); });
});

}  // namespace locus_cli_survey
