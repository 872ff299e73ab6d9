// Survey uploads into one RP, and a radio map's export and import as one document.
#include "http/app.hpp"
#include "http/transmitter_fields.hpp"
#include "http/store_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_radiomap_routes() {
    server_.Post(R"(/v1/rps/(\d+)/scans)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto rp_id = parse_id(req.matches[1].str(), "rp");
            const auto result = store_.merge_scans(rp_id, parse_scan_upload(req.body));
            return std::pair{200, json{{"applied", result.applied}, {"rp", rp_json(result.rp)}}};
        });
    });

    server_.Get(R"(/v1/radiomaps/(\d+)/export)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            return std::pair{200, export_json(store_.export_radiomap(parse_id(req.matches[1].str(), "radiomap")))};
        });
    });

    server_.Post(R"(/v1/floors/(\d+)/radiomaps/import)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const auto doc = parse_radiomap_document(parse_object(req.body));
            if (!doc.transmitters.empty()) {
                const store::Record floor = store_.get(store::kind("floors"), floor_id);
                for (std::size_t i = 0; i < doc.transmitters.size(); ++i) try {
                        check_on_floor(floor, doc.transmitters[i].get<double>("x"), doc.transmitters[i].get<double>("y"));
                    } catch (const ApiError& e) {
                        throw ApiError(e.status, e.code, "transmitters[" + std::to_string(i) + "]: " + e.what());
                    }
            }
            return std::pair{201, imported_json(store_.import_radiomap(floor_id, doc))};
        });
    });

    install_tune_routes();
}

}  // namespace locus::http
