// Survey uploads into one RP, and a radio map's export and import as one document.
#include <cstdio>
#include <memory>

#include "http/app.hpp"
#include "http/export_stream.hpp"
#include "http/json_text.hpp"
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

    // Written out as it is read, from one snapshot: a large radio map is never whole in memory.
    server_.Get(R"(/v1/radiomaps/(\d+)/export)", [this](const httplib::Request& req, httplib::Response& res) {
        guarded(req, res, [&] {
            auto stream = std::make_shared<ExportStream>(store_.read_radiomap(parse_id(req.matches[1].str(), "radiomap")));
            res.status = 200;
            res.set_chunked_content_provider("application/json", [stream](std::size_t, httplib::DataSink& sink) {
                try {
                    const std::string piece = stream->next();
                    if (piece.empty()) {
                        sink.done();
                        return true;
                    }
                    return sink.write(piece.data(), piece.size());
                } catch (const std::exception& e) {
                    // The status is sent: the connection is cut, so the client sees a broken
                    // answer rather than a short document.
                    std::fprintf(stderr, "{\"event\":\"export_failed\",\"message\":%s}\n", json_text(e.what()).c_str());
                    return false;
                }
            });
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
