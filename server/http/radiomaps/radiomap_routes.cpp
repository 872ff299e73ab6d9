// Survey uploads into one RP, and a radio map's export and import as one document.
#include <chrono>
#include <cstdio>
#include <memory>

#include "http/app.hpp"
#include "http/radiomaps/export_stream.hpp"
#include "http/json_text.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/crud/store_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

constexpr int kExportRetryAfterS = 5;  // an export takes seconds to minutes: no point asking every second

// One export being written: what it reads, the slot it holds, and when it is cut. It lives in
// the answer's content provider, which cpp-httplib destroys with the answer once it was written
// or its writing failed (a client gone, a write past the deadline): the reader (its connection
// and snapshot) and the slot go with it, however the answer ended.
class ExportJob {
public:
    using Clock = std::chrono::steady_clock;
    ExportJob(std::unique_ptr<store::RadioMapReader> reader, Slots::Held slot, std::chrono::milliseconds timeout, std::int64_t radiomap_id)
        : stream_(std::move(reader)), slot_(std::move(slot)), timeout_(timeout), deadline_(Clock::now() + timeout),
          radiomap_id_(radiomap_id) {}
    ExportJob(const ExportJob&) = delete;
    ExportJob& operator=(const ExportJob&) = delete;
    // Logged here rather than where the time ran out: cpp-httplib may give up on a write that
    // reached the deadline (its writability check) without asking the provider again.
    ~ExportJob() {
        if (!ended_ && !failed_ && Clock::now() >= deadline_)
            std::fprintf(stderr, "{\"event\":\"export_timeout\",\"radiomap_id\":%lld,\"timeout_s\":%g}\n",
                         static_cast<long long>(radiomap_id_), std::chrono::duration<double>(timeout_).count());
    }

    Clock::time_point deadline() const { return deadline_; }

    // cpp-httplib's chunked content provider. Returning false ends the answer without its last
    // chunk and closes the connection: a client sees a cut body, never a short document that parses.
    bool provide(httplib::DataSink& sink) {
        if (Clock::now() >= deadline_) return false;
        try {
            const std::string piece = stream_.next();
            if (piece.empty()) {
                ended_ = true;
                sink.done();
                return true;
            }
            return sink.write(piece.data(), piece.size());
        } catch (const std::exception& e) {
            failed_ = true;
            std::fprintf(stderr, "{\"event\":\"export_failed\",\"message\":%s}\n", json_text(e.what()).c_str());
            return false;
        }
    }

private:
    ExportStream stream_;
    Slots::Held slot_;
    std::chrono::milliseconds timeout_;
    Clock::time_point deadline_;
    std::int64_t radiomap_id_;
    bool ended_ = false, failed_ = false;
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
            auto job = std::make_shared<ExportJob>(store_.read_radiomap(id), std::move(slot), options_.export_timeout, id);
            Front::limit_writes(job->deadline());  // a write blocked on a client that stopped reading ends then too
            res.status = 200;
            res.set_chunked_content_provider("application/json",
                                             [job](std::size_t, httplib::DataSink& sink) { return job->provide(sink); });
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
