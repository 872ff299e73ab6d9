// GET /v1/radiomaps/{id}/quality?folds=&max_queries=: each RP's held-out error with the radio
// map's current settings (match::held_out_errors, tune's folds), for the viewer's
// predicted-error layer. Read only; bounded as tune is, and at most kQualityAtOnce run at a
// time: it is an open GET costing up to ~0.4 s of a core, so a burst answers 503 server_busy (with
// Retry-After) instead of queueing work that would starve localize.
//
// POST /v1/radiomaps/{id}/tune: cross-validates the radio map's own RPs over a small grid of
// matcher settings (match::tune), stores the best as the radio map's settings and answers the
// CV table. It runs on the request's thread over a snapshot of the RPs and holds no lock a
// localize needs: localize keeps the old settings until the new ones are committed, and the
// commit's change makes the index pick them up.
#include <chrono>
#include <unordered_map>

#include "http/app.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "http/front/slots.hpp"
#include "http/validation.hpp"
#include "locus/match/quality.hpp"
#include "locus/match/tune.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

match::TuneLimits parse_tune_body(const std::string& body) {
    match::TuneLimits limits;
    if (body.empty()) return limits;
    const json j = parse_object(body);
    only_fields(j, {"folds", "max_queries"}, "body");
    const auto integer = [&](const char* field, std::int64_t lo, std::int64_t hi, std::int64_t fallback) {
        if (!j.contains(field)) return fallback;
        const auto& v = j.at(field);
        if (!v.is_number_integer()) throw invalid_field("'" + std::string(field) + "' must be an integer");
        const auto n = v.get<std::int64_t>();
        if (n < lo || n > hi)
            throw ApiError(422, "out_of_range",
                           "'" + std::string(field) + "' must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return n;
    };
    limits.folds = static_cast<int>(integer("folds", 2, 50, limits.folds));
    limits.max_queries = static_cast<std::size_t>(integer("max_queries", 10, 5000, static_cast<std::int64_t>(limits.max_queries)));
    return limits;
}

}  // namespace

// One tune per radio map at a time: a second one would only compute the same table again.
class App::TuneGuard {
public:
    TuneGuard(App& app, std::int64_t id) : app_(app), id_(id) {
        std::lock_guard lock(app_.tuning_mu_);
        if (!app_.tuning_.insert(id_).second)
            throw ApiError(409, "tune_running", "radiomap " + std::to_string(id_) + " is being tuned already; try again when it is done");
    }
    ~TuneGuard() {
        std::lock_guard lock(app_.tuning_mu_);
        app_.tuning_.erase(id_);
    }
    TuneGuard(const TuneGuard&) = delete;
    TuneGuard& operator=(const TuneGuard&) = delete;

private:
    App& app_;
    std::int64_t id_;
};

namespace {

constexpr int kQualityAtOnce = 2;
Slots quality_slots(kQualityAtOnce);

// A radio map's RPs as the matchers index them, read once (one consistent snapshot), and the
// level of each floor they are on, for the floor penalty.
struct Snapshot {
    std::vector<match::IndexedRp> rps;
    std::unordered_map<long long, long long> levels;
};
Snapshot snapshot_of(store::Store& store, std::int64_t radiomap_id) {
    Snapshot out;
    auto stored = store.rps_of_radiomap(radiomap_id);
    out.rps.reserve(stored.size());
    for (auto& s : stored) {
        if (!out.levels.count(s.floor_id))
            out.levels[s.floor_id] = store.get(store::kind("floors"), s.floor_id).fields.get<std::int64_t>("level");
        out.rps.push_back({std::move(s.rp), s.floor_id, s.building_id});
    }
    return out;
}

}  // namespace

void App::install_tune_routes() {
    server_.Get(R"(/v1/radiomaps/(\d+)/quality)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "radiomap");
            match::TuneLimits limits;
            if (req.has_param("folds")) limits.folds = static_cast<int>(parse_query_integer(req.get_param_value("folds"), "folds", 2, 50));
            if (req.has_param("max_queries"))
                limits.max_queries = static_cast<std::size_t>(parse_query_integer(req.get_param_value("max_queries"), "max_queries", 10, 5000));
            store_.get(store::kind("radiomaps"), id);  // 404 before anything else
            // Bad input and 404 cost nothing and are never busy.
            const auto slot = quality_slots.take(res, std::to_string(kQualityAtOnce) +
                                                          " quality assessments are running already; retry in a second");
            const auto stored_settings = store_.settings_of_radiomap(id);
            const match::Setting setting = stored_settings ? settings_of_text(stored_settings->settings) : match::Setting{};
            Snapshot snap = snapshot_of(store_, id);  // named, not bound: clang 14 lambdas cannot capture bindings
            match::QualityReport report;
            try {
                report = match::held_out_errors(snap.rps, setting, [&snap](long long floor) { return snap.levels[floor]; }, limits);
            } catch (const match::TuneRefused& e) {
                throw ApiError(422, "cannot_assess", "radiomap " + std::to_string(id) + ": " + e.what());
            }
            json items = json::array();
            double sum = 0;
            for (const auto& q : report.rps) {
                const auto& r = snap.rps[q.rp];
                json j = {{"id", r.rp.id}, {"name", r.rp.name}, {"floor_id", r.floor_id}, {"x", r.rp.at.x}, {"y", r.rp.at.y},
                          {"error_m", nullptr}, {"horizontal_m", nullptr}, {"floor_ok", q.floor_ok}};
                if (q.error_m) {
                    j["error_m"] = *q.error_m;
                    sum += *q.error_m;
                }
                if (q.horizontal_m) j["horizontal_m"] = *q.horizontal_m;
                items.push_back(std::move(j));
            }
            json out{{"radiomap_id", id}, {"settings", settings_json(setting)}, {"folds", report.folds}, {"queries", report.queries},
                     {"subsampled", report.subsampled}, {"mean_error_m", sum / static_cast<double>(report.queries)}, {"rps", std::move(items)}};
            out["settings"]["source"] = stored_settings ? "tuned" : "built-in";
            return std::pair{200, std::move(out)};
        });
    });

    server_.allow_no_body("POST", R"(/v1/radiomaps/(\d+)/tune)");  // the defaults
    server_.Post(R"(/v1/radiomaps/(\d+)/tune)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "radiomap");
            const auto limits = parse_tune_body(req.body);
            store_.get(store::kind("radiomaps"), id);  // 404 before anything else
            TuneGuard guard(*this, id);
            const auto t0 = std::chrono::steady_clock::now();
            Snapshot snap = snapshot_of(store_, id);  // named, not bound: clang 14 lambdas cannot capture bindings
            const auto grid = match::tune_grid();
            match::TuneReport report;
            try {
                report = match::tune(snap.rps, grid, [&snap](long long floor) { return snap.levels[floor]; }, limits);
            } catch (const match::TuneRefused& e) {
                throw ApiError(422, "cannot_tune", "radiomap " + std::to_string(id) + ": " + e.what());
            }
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const auto& best = report.rows[report.best];
            json table = tune_json(report, seconds);
            store::RadiomapSettings settings{settings_json(best.setting).dump(), table.dump(), {}};
            const auto written = store_.put_radiomap_settings(id, settings);
            json out{{"radiomap_id", id}, {"settings", settings_json(best.setting)}, {"tune", std::move(table)}};
            out["settings"]["source"] = "tuned";
            out["settings"]["updated_at"] = written.updated_at;
            return std::pair{200, std::move(out)};
        });
    });
}

}  // namespace locus::http
