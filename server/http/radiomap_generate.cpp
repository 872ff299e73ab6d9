// POST /v1/floors/{id}/radiomaps/generate: a radio map with no survey, from the floor's
// transmitters and its plan's walls (ranging/propagation.hpp). Each RP is a grid point, marked
// generated; each AP's mean is the multi-wall model's RSS and its variance sigma_db² (the
// shadowing a fit leaves, e.g. the residual_db of …/transmitters/fit).
#include <nlohmann/json.hpp>
#include <string>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/radiomap_generate.hpp"
#include "http/store_json.hpp"
#include "http/transmitter_fields.hpp"
#include "http/validation.hpp"
#include "locus/ranging/propagation.hpp"
#include "store/kinds.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
// A grid finer than this many RPs is refused: one request must stay one bounded transaction.
constexpr std::size_t kMaxGeneratedRps = 100'000;
}  // namespace

void install_radiomap_generate(httplib::Server& server, store::Store& store) {
    server.Post(R"(/v1/floors/(\d+)/radiomaps/generate)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const json body = parse_object(req.body);
            only_fields(body, {"name", "description", "step", "min_rss", "sigma_db", "phone_height"}, "");
            store::RadioMapDocument doc;
            {
                json fields = json::object();
                for (const char* k : {"name", "description"})
                    if (body.contains(k)) fields[k] = body.at(k);
                doc.fields = validated_fields(store::kind("radiomaps"), fields, true);
            }
            const double step = finite_number(body, "step", "", 0.1, 1000.0);
            const double min_rss = body.contains("min_rss") ? finite_number(body, "min_rss", "", kMinRss, kMaxRss) : -95.0;
            const double sigma = body.contains("sigma_db") ? finite_number(body, "sigma_db", "", 0.0, 30.0) : 4.0;
            const double phone_height = body.contains("phone_height") ? finite_number(body, "phone_height", "", -10.0, 100.0) : 1.2;

            const store::Record floor = store.get(store::kind("floors"), floor_id);
            const Rect area{0, 0, floor.fields.get<double>("width"), floor.fields.get<double>("height")};
            const double cells = std::ceil(area.xmax / step) * std::ceil(area.ymax / step);
            if (cells > static_cast<double>(kMaxGeneratedRps))
                throw ApiError(422, "out_of_range",
                               "'step' = " + json(step).dump() + " makes " + json(cells).dump() + " RPs on this floor; at most " +
                                   std::to_string(kMaxGeneratedRps));
            std::vector<ranging::ModelledTransmitter> txs;
            std::vector<Measurement> ids;  // type and bssid of each, by index
            for (const auto& r : transmitters_of_floor(store, floor_id)) {
                const auto& f = r.fields;
                ranging::ModelledTransmitter t;
                t.tx.at = {f.get<double>("x"), f.get<double>("y")};
                const auto& z = f.values.at("z");
                t.tx.dz = std::holds_alternative<double>(z) ? std::get<double>(z) - phone_height : 0.0;
                t.tx.model = {f.get<double>("tx_power"), f.get<double>("path_loss_exponent")};
                const auto& wa = f.values.at("wall_attenuation");
                if (std::holds_alternative<double>(wa)) t.wall_attenuation = std::get<double>(wa);
                txs.push_back(t);
                Measurement m;
                m.type = f.get<std::string>("type");
                m.bssid = Bssid::stored(f.get<std::string>("bssid"));
                ids.push_back(std::move(m));
            }
            if (txs.empty())
                throw ApiError(422, "no_transmitters", "floor " + std::to_string(floor_id) + " has no transmitters to model a radio map from");
            std::vector<Segment> walls;
            if (const auto plan = store.plan_of_floor(floor_id))
                for (const auto& w : plan->plan.walls)
                    for (std::size_t i = 1; i < w.line.size(); ++i) walls.push_back({w.line[i - 1], w.line[i]});
            const ranging::WallIndex index(walls);

            std::size_t i = 0;
            for (const Point p : ranging::grid_points(area, step)) {
                store::RpDocument rp;
                rp.name = "grid " + std::to_string(i++);
                rp.at = p;
                rp.scans = 1;
                rp.generated = true;
                for (const auto& r : ranging::modelled_rss(p, txs, index, min_rss)) {
                    Measurement m = ids[r.transmitter];
                    // The variance is bounded by what RSS in [-120, 0] with this mean can spread.
                    const double bound = (kMaxRss - r.rss) * (r.rss - kMinRss);
                    m.stats = RssStats{r.rss, std::min(sigma * sigma, std::max(bound, 0.0)), 1};
                    rp.measurements.push_back(std::move(m));
                }
                doc.rps.push_back(std::move(rp));
            }
            const auto imported = store.import_radiomap(floor_id, doc);
            json out = imported_json(imported);
            out["generated"] = true;
            out["walls"] = walls.size();
            out["transmitters"] = txs.size();
            res.set_header("Location", "/v1/radiomaps/" + std::to_string(imported.radiomap.id));
            return std::pair{201, out};
        });
    });
}

}  // namespace locus::http
