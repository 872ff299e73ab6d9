#include "transmitters/generate.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <variant>
#include <vector>

#include "locus/radio_map.hpp"
#include "locus/ranging/propagation.hpp"
#include "store/kinds.hpp"
#include "transmitters/floor_transmitters.hpp"
#include "transmitters/refused.hpp"

namespace locus::transmitters {

namespace {

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
        throw Refused("no_transmitters", "floor " + std::to_string(floor_id) + " has no transmitters to model a radio map from");
    std::vector<Segment> walls;
    if (const auto plan = store.plan_of_floor(floor_id))
        for (const auto& w : plan->plan.walls)
            for (std::size_t i = 1; i < w.line.size(); ++i) walls.push_back({w.line[i - 1], w.line[i]});
    model.walls = walls.size();
    model.index = ranging::WallIndex(walls);
    return model;
}

store::RpDocument modelled_rp(std::string name, Point p, const FloorModel& model, const ModelOptions& o) {
    store::RpDocument rp;
    rp.name = std::move(name);
    rp.at = p;
    rp.scans = 1;
    rp.generated = true;
    rp.measurements = model.at(p, o.min_rss, o.sigma);
    return rp;
}

// The box of the stored RPs.
Rect box_of(const std::vector<store::StoredRp>& stored) {
    Rect box{stored[0].rp.at.x, stored[0].rp.at.y, stored[0].rp.at.x, stored[0].rp.at.y};
    for (const auto& s : stored) {
        box.xmin = std::min(box.xmin, s.rp.at.x);
        box.ymin = std::min(box.ymin, s.rp.at.y);
        box.xmax = std::max(box.xmax, s.rp.at.x);
        box.ymax = std::max(box.ymax, s.rp.at.y);
    }
    return box;
}

}  // namespace

Generated generate_radiomap(store::Store& store, const GenerateRequest& request) {
    const double step = request.step;
    const store::Record floor = store.get(store::kind("floors"), request.floor_id);
    const Rect area{0, 0, floor.fields.get<double>("width"), floor.fields.get<double>("height")};
    const double cells = std::ceil(area.xmax / step) * std::ceil(area.ymax / step);
    if (cells > static_cast<double>(kMaxGeneratedRps)) throw GridTooFine(step, cells, false);
    const FloorModel model = floor_model(store, request.floor_id, request.model.phone_height);
    store::RadioMapDocument doc;
    doc.fields = request.fields;
    std::size_t i = 0;
    for (const Point p : ranging::grid_points(area, step))
        doc.rps.push_back(modelled_rp("grid " + std::to_string(i++), p, model, request.model));
    Generated out;
    out.imported = store.import_radiomap(request.floor_id, doc);
    out.transmitters = model.txs.size();
    out.walls = model.walls;
    return out;
}

Densified densify_radiomap(store::Store& store, const DensifyRequest& request) {
    const double step = request.step;
    const store::Record radiomap = store.get(store::kind("radiomaps"), request.radiomap_id);
    const auto stored = store.rps_of_radiomap(request.radiomap_id);
    if (stored.size() < 2)
        throw Refused("too_few_rps", "radiomap " + std::to_string(request.radiomap_id) + " has " + std::to_string(stored.size()) +
                                         " RP" + (stored.size() == 1 ? "" : "s") + "; densify fills between at least 2");
    const Rect box = box_of(stored);
    const double cells = std::ceil((box.xmax - box.xmin) / step + 1) * std::ceil((box.ymax - box.ymin) / step + 1);
    if (cells > static_cast<double>(kMaxGeneratedRps)) throw GridTooFine(step, cells, true);
    const std::int64_t floor_id = radiomap.parent_id.value_or(0);
    const FloorModel model = floor_model(store, floor_id, request.model.phone_height);
    // Grid nodes on the box's edges too, so the fill reaches the outermost RPs.
    // Clipped to the floor: an RP by a wall must not put modelled RPs outside the building.
    const store::Record floor = store.get(store::kind("floors"), floor_id);
    const Rect area{std::max(0.0, box.xmin - step / 2), std::max(0.0, box.ymin - step / 2),
                    std::min(floor.fields.get<double>("width"), box.xmax + step / 2),
                    std::min(floor.fields.get<double>("height"), box.ymax + step / 2)};
    std::vector<store::RpDocument> added;
    for (const Point p : ranging::grid_points(area, step)) {
        // At least step/2 from every stored RP, so a surveyed RP is never shadowed and a second
        // densify adds only what is missing.
        bool near = false;
        for (const auto& s : stored) near = near || std::hypot(s.rp.at.x - p.x, s.rp.at.y - p.y) < step / 2;
        if (near) continue;
        added.push_back(modelled_rp(request.name_of(p), p, model, request.model));
    }
    Densified out;
    out.surveyed_rps = stored.size();
    out.added = store.add_rps(request.radiomap_id, added);
    out.transmitters = model.txs.size();
    out.walls = model.walls;
    return out;
}

}  // namespace locus::transmitters
