// POST /v1/floors/{id}/radiomaps/generate: a radio map with no survey, from the floor's
// transmitters and its plan's walls (ranging/propagation.hpp). Each RP is a grid point, marked
// generated; each AP's mean is the multi-wall model's RSS and its variance sigma_db² (the
// shadowing a fit leaves, e.g. the residual_db of …/transmitters/fit).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/radiomaps/radiomap_generate.hpp"
#include "http/crud/store_json.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/validation.hpp"
#include "locus/ranging/propagation.hpp"
#include "store/kinds.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
// A grid finer than this many RPs is refused: one request must stay one bounded transaction.
constexpr std::size_t kMaxGeneratedRps = 100'000;

// The floor's transmitters and its plan's walls, ready to model the RSS anywhere on it.
struct FloorModel {
    std::vector<ranging::ModelledTransmitter> txs;
    std::vector<Measurement> ids;  // type and bssid of each, by index
    std::size_t walls = 0;
    ranging::WallIndex index{{}};

    // Every AP heard at p above min_rss, mean the model's RSS, variance sigma_db².
    std::vector<Measurement> at(Point p, double min_rss, double sigma) const {
        std::vector<Measurement> out;
        for (const auto& r : ranging::modelled_rss(p, txs, index, min_rss)) {
            Measurement m = ids[r.transmitter];
            // The variance is bounded by what RSS in [-120, 0] with this mean can spread.
            const double bound = (kMaxRss - r.rss) * (r.rss - kMinRss);
            m.stats = RssStats{r.rss, std::min(sigma * sigma, std::max(bound, 0.0)), 1};
            out.push_back(std::move(m));
        }
        return out;
    }
};

FloorModel floor_model(store::Store& store, std::int64_t floor_id, double phone_height) {
    FloorModel model;
    auto& txs = model.txs;
    auto& ids = model.ids;
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
    model.walls = walls.size();
    model.index = ranging::WallIndex(walls);
    return model;
}

// Model parameters shared by generate and densify.
struct ModelOptions {
    double min_rss = -95.0, sigma = 4.0, phone_height = 1.2;
};

ModelOptions model_options(const json& body) {
    ModelOptions o;
    if (body.contains("min_rss")) o.min_rss = finite_number(body, "min_rss", "", kMinRss, kMaxRss);
    if (body.contains("sigma_db")) o.sigma = finite_number(body, "sigma_db", "", 0.0, 30.0);
    if (body.contains("phone_height")) o.phone_height = finite_number(body, "phone_height", "", -10.0, 100.0);
    return o;
}
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
            const ModelOptions o = model_options(body);

            const store::Record floor = store.get(store::kind("floors"), floor_id);
            const Rect area{0, 0, floor.fields.get<double>("width"), floor.fields.get<double>("height")};
            const double cells = std::ceil(area.xmax / step) * std::ceil(area.ymax / step);
            if (cells > static_cast<double>(kMaxGeneratedRps))
                throw ApiError(422, "out_of_range",
                               "'step' = " + json(step).dump() + " makes " + json(cells).dump() + " RPs on this floor; at most " +
                                   std::to_string(kMaxGeneratedRps));
            const FloorModel model = floor_model(store, floor_id, o.phone_height);
            const auto& txs = model.txs;
            std::size_t i = 0;
            for (const Point p : ranging::grid_points(area, step)) {
                store::RpDocument rp;
                rp.name = "grid " + std::to_string(i++);
                rp.at = p;
                rp.scans = 1;
                rp.generated = true;
                rp.measurements = model.at(p, o.min_rss, o.sigma);
                doc.rps.push_back(std::move(rp));
            }
            const auto imported = store.import_radiomap(floor_id, doc);
            json out = imported_json(imported);
            out["generated"] = true;
            out["walls"] = model.walls;
            out["transmitters"] = txs.size();
            res.set_header("Location", "/v1/radiomaps/" + std::to_string(imported.radiomap.id));
            return std::pair{201, out};
        });
    });
    // Fills a sparse survey between its RPs with the floor's calibrated model: grid points of
    // `step` inside the box of the radio map's RPs, each at least step/2 from every stored RP
    // (so a surveyed RP is never shadowed and a second densify adds only what is missing).
    server.Post(R"(/v1/radiomaps/(\d+)/densify)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto radiomap_id = parse_id(req.matches[1].str(), "radiomap");
            const json body = parse_object(req.body);
            only_fields(body, {"step", "min_rss", "sigma_db", "phone_height"}, "");
            const double step = finite_number(body, "step", "", 0.1, 1000.0);
            const ModelOptions o = model_options(body);
            const store::Record radiomap = store.get(store::kind("radiomaps"), radiomap_id);
            const auto stored = store.rps_of_radiomap(radiomap_id);
            if (stored.size() < 2)
                throw ApiError(422, "too_few_rps",
                               "radiomap " + std::to_string(radiomap_id) + " has " + std::to_string(stored.size()) +
                                   " RP" + (stored.size() == 1 ? "" : "s") + "; densify fills between at least 2");
            Rect box{stored[0].rp.at.x, stored[0].rp.at.y, stored[0].rp.at.x, stored[0].rp.at.y};
            for (const auto& s : stored) {
                box.xmin = std::min(box.xmin, s.rp.at.x);
                box.ymin = std::min(box.ymin, s.rp.at.y);
                box.xmax = std::max(box.xmax, s.rp.at.x);
                box.ymax = std::max(box.ymax, s.rp.at.y);
            }
            const double cells = std::ceil((box.xmax - box.xmin) / step + 1) * std::ceil((box.ymax - box.ymin) / step + 1);
            if (cells > static_cast<double>(kMaxGeneratedRps))
                throw ApiError(422, "out_of_range",
                               "'step' = " + json(step).dump() + " makes " + json(cells).dump() + " RPs between this radio map's RPs; at most " +
                                   std::to_string(kMaxGeneratedRps));
            const FloorModel model = floor_model(store, radiomap.parent_id.value_or(0), o.phone_height);
            // Grid nodes on the box's edges too, so the fill reaches the outermost RPs.
            // Clipped to the floor: an RP by a wall must not put modelled RPs outside the building.
            const store::Record floor = store.get(store::kind("floors"), radiomap.parent_id.value_or(0));
            const Rect area{std::max(0.0, box.xmin - step / 2), std::max(0.0, box.ymin - step / 2),
                            std::min(floor.fields.get<double>("width"), box.xmax + step / 2),
                            std::min(floor.fields.get<double>("height"), box.ymax + step / 2)};
            std::vector<store::RpDocument> added;
            for (const Point p : ranging::grid_points(area, step)) {
                bool near = false;
                for (const auto& s : stored) near = near || std::hypot(s.rp.at.x - p.x, s.rp.at.y - p.y) < step / 2;
                if (near) continue;
                store::RpDocument rp;
                rp.name = "dense " + json(p.x).dump() + " " + json(p.y).dump();
                rp.at = p;
                rp.scans = 1;
                rp.generated = true;
                rp.measurements = model.at(p, o.min_rss, o.sigma);
                added.push_back(std::move(rp));
            }
            const auto result = store.add_rps(radiomap_id, added);
            return std::pair{200, json{{"radiomap_id", radiomap_id},
                                       {"surveyed_rps", stored.size()},
                                       {"added_rps", result.rp_count},
                                       {"measurement_count", result.measurement_count},
                                       {"transmitters", model.txs.size()},
                                       {"walls", model.walls}}};
        });
    });
}

}  // namespace locus::http
