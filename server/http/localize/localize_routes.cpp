// POST /v1/radiomaps/{id}/localize and POST /v1/maps/{id}/localize: one scan against one
// radio map's or one map's index.
#include <string>
#include <tuple>

#include "http/app.hpp"
#include "http/localize/localize_answer.hpp"
#include "http/localize/localize_request.hpp"
#include "http/localize/ranging_localize.hpp"
#include "http/validation.hpp"

namespace locus::http {

void App::install_localize() {
    using Scope = localize::Service::Scope;
    for (const auto& [collection, what, scope] :
         {std::tuple{"radiomaps", "radiomap", Scope::radiomap}, std::tuple{"maps", "map", Scope::map}}) {
        server_.Post("/v1/" + std::string(collection) + R"(/(\d+)/localize)",
                     // Init-captures: clang before 16 cannot capture structured bindings.
                     [this, what = what, scope = scope](const httplib::Request& req, httplib::Response& res) {
                         guarded(req, res, [&] {
                             const auto id = parse_id(req.matches[1].str(), what);
                             if (const auto ranging = parse_ranging_request(req.body)) {
                                 res.set_content(ranging_answer(store_, transmitters_, views_, scope == Scope::map, id, *ranging), "application/json");
                                 return;
                             }
                             const auto request = parse_localize_request(req.body);
                             // Moved in: set_content would copy the answer. As set_content
                             // does, any earlier Content-Type goes.
                             res.body = answer(*localizer_.lookup(scope, id), request, &geo_, &places_);
                             res.headers.erase("Content-Type");
                             res.set_header("Content-Type", "application/json");
                         });
                     });
    }
}

}  // namespace locus::http
