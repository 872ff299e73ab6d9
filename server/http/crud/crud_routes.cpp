// The hierarchy's CRUD routes, one set per kind (store/kinds.hpp): POST and GET on the
// collection (nested under the parent), GET, PATCH and DELETE on an item.
#include "http/app.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "http/crud/store_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
std::string collection_path(const store::Kind& k) {
    return k.parent_column.empty() ? "/v1/" + std::string(k.name)
                                   : "/v1/" + std::string(k.parent_kind) + R"(/(\d+)/)" + std::string(k.name);
}
}  // namespace

void App::install_crud() {
    for (const auto& k : store::kinds()) {
        if (k.name == "transmitters") continue;  // transmitter_routes.cpp: checks beyond the fields
        const store::Kind* kp = &k;
        const std::string collection = collection_path(k);
        const std::string item = "/v1/" + std::string(k.name) + R"(/(\d+))";
        const bool nested = !k.parent_column.empty();
        const std::string parent_singular = nested ? std::string(store::kind(k.parent_kind).singular) : "";

        server_.Post(collection, [this, kp, nested, parent_singular](const httplib::Request& req, httplib::Response& res) {
            respond(req, res, [&] {
                std::optional<std::int64_t> parent;
                if (nested) parent = parse_id(req.matches[1].str(), parent_singular);
                const store::Record row = store_.create(*kp, parent, validated_fields(*kp, parse_object(req.body), true));
                res.set_header("Location", "/v1/" + std::string(kp->name) + "/" + std::to_string(row.id));
                return std::pair{201, record_json(*kp, row)};
            });
        });
        server_.Get(collection, [this, kp, nested, parent_singular](const httplib::Request& req, httplib::Response& res) {
            respond(req, res, [&] {
                std::optional<std::int64_t> parent;
                if (nested) parent = parse_id(req.matches[1].str(), parent_singular);
                auto param = [&](const char* name) -> std::optional<std::string> {
                    if (!req.has_param(name)) return std::nullopt;
                    return req.get_param_value(name);
                };
                const Page page = parse_page(param("limit"), param("offset"));
                return std::pair{200, page_json(*kp, store_.list(*kp, parent, page.limit, page.offset))};
            });
        });
        server_.Get(item, [this, kp](const httplib::Request& req, httplib::Response& res) {
            respond(req, res, [&] {
                const auto id = parse_id(req.matches[1].str(), kp->singular);
                // An RP is read with its measurements: that is what a client wants from it.
                if (kp->name == "rps") return std::pair{200, rp_json(store_.rp_with_measurements(id))};
                // A radio map is read with its matcher settings and its last tune's figures.
                if (kp->name == "radiomaps") {
                    auto j = record_json(*kp, store_.get(*kp, id));
                    add_settings(j, store_.settings_of_radiomap(id));
                    return std::pair{200, std::move(j)};
                }
                return std::pair{200, record_json(*kp, store_.get(*kp, id))};
            });
        });
        server_.Patch(item, [this, kp](const httplib::Request& req, httplib::Response& res) {
            respond(req, res, [&] {
                const auto id = parse_id(req.matches[1].str(), kp->singular);
                const store::Record row = store_.update(*kp, id, validated_fields(*kp, parse_object(req.body), false));
                return std::pair{200, record_json(*kp, row)};
            });
        });
        server_.Delete(item, [this, kp](const httplib::Request& req, httplib::Response& res) {
            respond(req, res, [&] {
                store_.remove(*kp, parse_id(req.matches[1].str(), kp->singular));
                return std::pair{204, json()};
            });
        });
    }
}

}  // namespace locus::http
