// A floor's transmitters (WiFi APs and BLE beacons at known positions): the CRUD routes of the
// "transmitters" kind, with the checks a field alone cannot make (transmitter_fields.hpp): the
// generic CRUD of crud_routes.cpp leaves this kind to this file.
#include <string>

#include "http/app.hpp"
#include "http/crud/store_json.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/transmitters/transmitter_fit.hpp"
#include "http/radiomaps/radiomap_generate.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

const store::Kind& transmitters() { return store::kind("transmitters"); }
const store::Kind& floors() { return store::kind("floors"); }

// The one UNIQUE of the table is (floor_id, type, bssid): name the id that is taken.
template <typename F>
store::Record naming_duplicates(const store::Fields& f, F&& write) {
    try {
        return write();
    } catch (const store::Conflict&) {
        std::string what = "this floor already has a transmitter";
        if (f.has("type") && f.has("bssid"))
            what += " of type '" + f.get<std::string>("type") + "' and bssid '" + f.get<std::string>("bssid") + "'";
        else
            what += " with that type and bssid";
        throw ApiError(409, "conflict", what);
    }
}

}  // namespace

void App::install_transmitter_routes() {
    server_.allow_no_body("POST", R"(/v1/floors/(\d+)/transmitters/fit)");  // ?apply=true alone
    install_transmitter_fit(server_, store_);
    install_radiomap_generate(server_, store_);
    server_.Post(R"(/v1/floors/(\d+)/transmitters)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const store::Fields f = transmitter_fields(parse_object(req.body), true);
            check_on_floor(store_.get(floors(), floor_id), f.get<double>("x"), f.get<double>("y"));
            const store::Record row = naming_duplicates(f, [&] { return store_.create(transmitters(), floor_id, f); });
            res.set_header("Location", "/v1/transmitters/" + std::to_string(row.id));
            return std::pair{201, record_json(transmitters(), row)};
        });
    });
    server_.Get(R"(/v1/floors/(\d+)/transmitters)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            auto param = [&](const char* name) -> std::optional<std::string> {
                if (!req.has_param(name)) return std::nullopt;
                return req.get_param_value(name);
            };
            const Page page = parse_page(param("limit"), param("offset"));
            return std::pair{200, page_json(transmitters(), store_.list(transmitters(), floor_id, page.limit, page.offset))};
        });
    });
    server_.Get(R"(/v1/transmitters/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "transmitter");
            return std::pair{200, record_json(transmitters(), store_.get(transmitters(), id))};
        });
    });
    server_.Patch(R"(/v1/transmitters/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "transmitter");
            store::Fields f = transmitter_fields(parse_object(req.body), false);
            const store::Record now = store_.get(transmitters(), id);
            // The position after the patch must lie on the floor (the floor's size may have
            // changed since, but a moved transmitter is checked against the size of today).
            if (f.has("x") || f.has("y")) {
                const double x = f.has("x") ? f.get<double>("x") : now.fields.get<double>("x");
                const double y = f.has("y") ? f.get<double>("y") : now.fields.get<double>("y");
                check_on_floor(store_.get(floors(), now.parent_id.value()), x, y);
            }
            store::Fields named = f;  // for the duplicate message: the id after the patch
            for (const char* key : {"type", "bssid"})
                if (!named.has(key)) named.values[key] = now.fields.values.at(key);
            const store::Record row = naming_duplicates(named, [&] { return store_.update(transmitters(), id, f); });
            return std::pair{200, record_json(transmitters(), row)};
        });
    });
    server_.Delete(R"(/v1/transmitters/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            store_.remove(transmitters(), parse_id(req.matches[1].str(), "transmitter"));
            return std::pair{204, json()};
        });
    });
}

}  // namespace locus::http
