// GET /v1/radiomaps/{id}/quality?folds=&max_queries= and POST /v1/radiomaps/{id}/tune: the
// routes of the tuning service (tuning/service.hpp), which assesses and tunes a radio map's
// matcher settings. A busy quality answers 503 server_busy with Retry-After, a second tune of
// one radio map 409 tune_running.
#include "http/app.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "http/radiomaps/tuning_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

namespace {

// The tuning service's refusals as the API answers them; `what` names the route's failure.
template <class F>
auto refusals_answered(httplib::Response& res, std::int64_t id, const char* cannot, F&& run) {
    try {
        return run();
    } catch (const tuning::Busy& e) {
        res.set_header("Retry-After", "1");
        throw ApiError(503, "server_busy", e.what());
    } catch (const tuning::Running& e) {
        throw ApiError(409, "tune_running", e.what());
    } catch (const match::TuneRefused& e) {
        throw ApiError(422, cannot, "radiomap " + std::to_string(id) + ": " + e.what());
    }
}

}  // namespace

void App::install_tune_routes() {
    server_.Get(R"(/v1/radiomaps/(\d+)/quality)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "radiomap");
            const auto limits = parse_quality_query(req);
            const auto quality = refusals_answered(res, id, "cannot_assess", [&] { return tuning_.quality(id, limits); });
            return std::pair{200, quality_json(id, quality)};
        });
    });

    server_.allow_no_body("POST", R"(/v1/radiomaps/(\d+)/tune)");  // the defaults
    server_.Post(R"(/v1/radiomaps/(\d+)/tune)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "radiomap");
            const auto limits = parse_tune_body(req.body);
            const auto tuned = refusals_answered(res, id, "cannot_tune", [&] { return tuning_.tune(id, limits); });
            return std::pair{200, tuned_json(id, tuned)};
        });
    });
}

}  // namespace locus::http
