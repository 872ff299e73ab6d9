#include "http/transmitters/transmitter_fit.hpp"

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/transmitters/transmitter_fit_json.hpp"
#include "http/validation.hpp"
#include "transmitters/fit.hpp"
#include "transmitters/refused.hpp"

namespace locus::http {

void install_transmitter_fit(httplib::Server& server, store::Store& store) {
    server.Post(R"(/v1/floors/(\d+)/transmitters/fit)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const auto request = parse_fit_request(req, floor_id);
            try {
                return std::pair{200, fit_json(floor_id, transmitters::fit_transmitters(store, request))};
            } catch (const transmitters::Refused& e) {
                throw ApiError(422, e.code, e.what());
            }
        });
    });
}

}  // namespace locus::http
