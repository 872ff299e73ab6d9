// Survey uploads into one RP, and a radio map's export and import as one document.
#include <chrono>
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

namespace {

constexpr int kExportRetryAfterS = 5;  // an export takes seconds to minutes: no point asking every second

// One export being written: what it reads, the slot it holds, and when it is cut.
struct ExportJob {
    ExportJob(std::unique_ptr<store::RadioMapReader> reader, Slots::Held held, std::chrono::steady_clock::time_point until,
              std::int64_t id)
        : stream(std::move(reader)), slot(std::move(held)), deadline(until), radiomap_id(id) {}
    ExportStream stream;
    Slots::Held slot;
    std::chrono::steady_clock::time_point deadline;
    std::int64_t radiomap_id;
};

}  // namespace

void App::install_radiomap_routes() {
    server_.Post(R"(/v1/rps/(\d+)/scans)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto rp_id = parse_id(req.matches[1].str(), "rp");
            const auto result = store_.merge_scans(rp_id, parse_scan_upload(req.body));
            return std::pair{200, json{{"applied", result.applied}, {"rp", rp_json(result.rp)}}};
        });
    });

    // Written out as it is read, from one snapshot: a large radio map is never whole in memory.
    // Each export holds a connection and a read snapshot (SQLite's WAL cannot be reset behind
    // it, PostgreSQL's vacuum waits for it) for as long as its client reads, so at most
    // --max-exports run at once and none runs past --export-timeout.
    server_.Get(R"(/v1/radiomaps/(\d+)/export)", [this](const httplib::Request& req, httplib::Response& res) {
        guarded(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "radiomap");
            // Before any database work: a busy server answers 503 even for a radio map it
            // would not find.
            auto slot = export_slots_.take(res,
                                           std::to_string(options_.max_exports) +
                                               " radio map exports are being written already (the server's --max-exports); retry later",
                                           kExportRetryAfterS);
            const auto deadline = std::chrono::steady_clock::now() + options_.export_timeout;
            auto job = std::make_shared<ExportJob>(store_.read_radiomap(id), std::move(slot), deadline, id);
            Front::limit_writes(deadline);  // a write blocked on a client that stopped reading ends then too
            res.status = 200;
            // The provider (and with it the job: reader, snapshot, slot) lives in `res`, which
            // cpp-httplib destroys once the answer is written or its writing failed: when the
            // client went away, a write fails and the provider is dropped.
            const auto timeout_s = std::chrono::duration<double>(options_.export_timeout).count();
            res.set_chunked_content_provider("application/json", [job, timeout_s](std::size_t, httplib::DataSink& sink) {
                // Returning false ends the answer without its last chunk and closes the
                // connection: a client sees a cut body, never a short document that parses.
                try {
                    if (std::chrono::steady_clock::now() < job->deadline) {
                        const std::string piece = job->stream.next();
                        if (piece.empty()) {
                            sink.done();
                            return true;
                        }
                        if (sink.write(piece.data(), piece.size())) return true;
                        // A failed write is a client gone, or one that stopped reading until
                        // the deadline (Front::limit_writes).
                        if (std::chrono::steady_clock::now() < job->deadline) return false;
                    }
                    std::fprintf(stderr, "{\"event\":\"export_timeout\",\"radiomap_id\":%lld,\"timeout_s\":%g}\n",
                                 static_cast<long long>(job->radiomap_id), timeout_s);
                    return false;
                } catch (const std::exception& e) {
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
