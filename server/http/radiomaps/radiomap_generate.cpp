// POST /v1/floors/{id}/radiomaps/generate and POST /v1/radiomaps/{id}/densify: the routes of
// transmitters::generate_radiomap and densify_radiomap (transmitters/generate.hpp); their JSON
// is http/radiomap_generate_json.hpp.
#include "http/radiomaps/radiomap_generate.hpp"

#include <string>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/radiomaps/radiomap_generate_json.hpp"
#include "http/validation.hpp"
#include "transmitters/generate.hpp"
#include "transmitters/refused.hpp"

namespace locus::http {

void install_radiomap_generate(httplib::Server& server, store::Store& store) {
    server.Post(R"(/v1/floors/(\d+)/radiomaps/generate)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const auto request = parse_generate_request(req.body, floor_id);
            try {
                const auto generated = transmitters::generate_radiomap(store, request);
                res.set_header("Location", "/v1/radiomaps/" + std::to_string(generated.imported.radiomap.id));
                return std::pair{201, generated_json(generated)};
            } catch (const transmitters::GridTooFine& e) {
                throw grid_too_fine(e);
            } catch (const transmitters::Refused& e) {
                throw ApiError(422, e.code, e.what());
            }
        });
    });
    server.Post(R"(/v1/radiomaps/(\d+)/densify)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto radiomap_id = parse_id(req.matches[1].str(), "radiomap");
            const auto request = parse_densify_request(req.body, radiomap_id);
            try {
                return std::pair{200, densified_json(radiomap_id, transmitters::densify_radiomap(store, request))};
            } catch (const transmitters::GridTooFine& e) {
                throw grid_too_fine(e);
            } catch (const transmitters::Refused& e) {
                throw ApiError(422, e.code, e.what());
            }
        });
    });
}

}  // namespace locus::http
