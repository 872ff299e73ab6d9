// Floor plans in SQLite (schema/004_floor_plans.sql): one row per feature, one per point, tag
// and link. A PUT deletes the floor's features and writes them again; a plan of a few
// thousand points is a few thousand inserts in one transaction, milliseconds.
#include <map>
#include <utility>

#include "store/sql_store.hpp"

namespace locus::store {

namespace {

struct FeatureRow {
    const char* feature;
    std::int64_t seq;
    std::string_view name, kind;
    std::optional<std::string_view> ident;
    std::optional<std::int64_t> room_id;
    bool step_free = false;
    std::optional<double> seconds;
    std::optional<std::int64_t> poi_id = std::nullopt;
};

}  // namespace

void SqlStore::write_plan_features(std::int64_t floor_id, const plan::Plan& p) {
    Stmt feature(db_,
                 "INSERT INTO plan_features (floor_id, feature, seq, name, kind, ident, room_id, step_free, "
                 "seconds_per_level, poi_id) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    Stmt point(db_, "INSERT INTO plan_points (feature_id, ring, seq, x, y) VALUES (?, ?, ?, ?, ?)");
    Stmt tag(db_, "INSERT INTO plan_tags (feature_id, seq, tag) VALUES (?, ?, ?)");
    Stmt link(db_, "INSERT INTO plan_links (feature_id, seq, floor_id, connector) VALUES (?, ?, ?, ?)");

    const auto insert = [&](const FeatureRow& r) {
        feature.reset();
        feature.bind(1, floor_id).bind(2, std::string_view(r.feature)).bind(3, r.seq).bind(4, r.name).bind(5, r.kind);
        if (r.ident) feature.bind(6, *r.ident);
        else feature.bind_null(6);
        if (r.room_id) feature.bind(7, *r.room_id);
        else feature.bind_null(7);
        feature.bind(8, r.step_free ? 1 : 0);
        if (r.seconds) feature.bind(9, *r.seconds);
        else feature.bind_null(9);
        if (r.poi_id) feature.bind(10, *r.poi_id);
        else feature.bind_null(10);
        feature.run();
        return db_.last_insert_id();
    };
    const auto points = [&](std::int64_t id, std::int64_t ring, const std::vector<Point>& pts) {
        for (std::size_t i = 0; i < pts.size(); ++i) {
            point.reset();
            point.bind(1, id).bind(2, ring).bind(3, static_cast<std::int64_t>(i)).bind(4, pts[i].x).bind(5, pts[i].y).run();
        }
    };

    for (std::size_t i = 0; i < p.spaces.size(); ++i) {
        const auto& s = p.spaces[i];
        const auto id = insert({"space", static_cast<std::int64_t>(i), s.name, s.kind, std::nullopt, s.room_id, false, std::nullopt});
        points(id, 0, s.shape.outer);
        for (std::size_t h = 0; h < s.shape.holes.size(); ++h) points(id, static_cast<std::int64_t>(h + 1), s.shape.holes[h]);
        for (std::size_t t = 0; t < s.tags.size(); ++t) {
            tag.reset();
            tag.bind(1, id).bind(2, static_cast<std::int64_t>(t)).bind(3, s.tags[t]).run();
        }
    }
    for (std::size_t i = 0; i < p.walls.size(); ++i)
        points(insert({"wall", static_cast<std::int64_t>(i), "", "", std::nullopt, std::nullopt, false, std::nullopt}), 0, p.walls[i].line);
    for (std::size_t i = 0; i < p.doors.size(); ++i) {
        const auto& d = p.doors[i];
        std::vector<Point> pts{d.a};
        if (d.b.x != d.a.x || d.b.y != d.a.y) pts.push_back(d.b);
        points(insert({"door", static_cast<std::int64_t>(i), d.name, "", std::nullopt, std::nullopt, false, std::nullopt}), 0, pts);
    }
    for (std::size_t i = 0; i < p.connectors.size(); ++i) {
        const auto& c = p.connectors[i];
        const auto id = insert({"connector", static_cast<std::int64_t>(i), c.name, plan::connector_kind_name(c.kind), c.id, std::nullopt,
                                c.step_free, c.seconds_per_level, c.poi_id});
        points(id, 0, {c.at});
        for (std::size_t l = 0; l < c.links.size(); ++l) {
            link.reset();
            link.bind(1, id).bind(2, static_cast<std::int64_t>(l)).bind(3, c.links[l].floor_id).bind(4, c.links[l].connector).run();
        }
    }
}

std::optional<StoredPlan> SqlStore::read_plan(std::int64_t floor_id) {
    Stmt head(db_, "SELECT version, updated_at FROM floor_plans WHERE floor_id = ?");
    head.bind(1, floor_id);
    if (!head.step()) return std::nullopt;
    StoredPlan out;
    out.floor_id = floor_id;
    out.version = head.int64(0);
    out.updated_at = head.text(1);

    // Each feature row lands in its list; points, tags and links follow by feature id.
    struct Slot {
        std::string feature;
        std::size_t index;
    };
    std::map<std::int64_t, Slot> by_id;
    Stmt f(db_,
           "SELECT id, feature, name, kind, ident, room_id, step_free, seconds_per_level, poi_id FROM plan_features "
           "WHERE floor_id = ? ORDER BY feature, seq");
    f.bind(1, floor_id);
    auto& p = out.plan;
    while (f.step()) {
        const std::string feature = f.text(1);
        std::size_t index = 0;
        if (feature == "space") {
            plan::Space s;
            s.name = f.text(2);
            s.kind = f.text(3);
            if (!f.is_null(5)) s.room_id = f.int64(5);
            index = p.spaces.size();
            p.spaces.push_back(std::move(s));
        } else if (feature == "wall") {
            index = p.walls.size();
            p.walls.emplace_back();
        } else if (feature == "door") {
            index = p.doors.size();
            p.doors.push_back({{}, {}, f.text(2)});
        } else {
            plan::Connector c;
            c.name = f.text(2);
            c.kind = plan::connector_kind_named(f.text(3)).value_or(plan::ConnectorKind::stairs);
            c.id = f.is_null(4) ? "" : f.text(4);
            c.step_free = f.int64(6) != 0;
            if (!f.is_null(7)) c.seconds_per_level = f.real(7);
            if (!f.is_null(8)) c.poi_id = f.int64(8);
            index = p.connectors.size();
            p.connectors.push_back(std::move(c));
        }
        by_id[f.int64(0)] = {feature, index};
    }

    Stmt pts(db_,
             "SELECT pp.feature_id, pp.ring, pp.x, pp.y, pp.seq FROM plan_points pp JOIN plan_features f ON f.id = pp.feature_id "
             "WHERE f.floor_id = ? ORDER BY pp.feature_id, pp.ring, pp.seq");
    pts.bind(1, floor_id);
    while (pts.step()) {
        const auto& slot = by_id.at(pts.int64(0));
        const auto ring = static_cast<std::size_t>(pts.int64(1));
        const Point pt{pts.real(2), pts.real(3)};
        if (slot.feature == "space") {
            auto& shape = p.spaces[slot.index].shape;
            if (ring == 0) shape.outer.push_back(pt);
            else {
                if (shape.holes.size() < ring) shape.holes.resize(ring);
                shape.holes[ring - 1].push_back(pt);
            }
        } else if (slot.feature == "wall") {
            p.walls[slot.index].line.push_back(pt);
        } else if (slot.feature == "door") {
            auto& d = p.doors[slot.index];
            // A point door has one point (a == b); a segment door's second point is b.
            if (pts.int64(4) == 0) d.a = d.b = pt;
            else d.b = pt;
        } else {
            p.connectors[slot.index].at = pt;
        }
    }

    Stmt tags(db_, "SELECT t.feature_id, t.tag FROM plan_tags t JOIN plan_features f ON f.id = t.feature_id "
                   "WHERE f.floor_id = ? ORDER BY t.feature_id, t.seq");
    tags.bind(1, floor_id);
    while (tags.step()) p.spaces[by_id.at(tags.int64(0)).index].tags.push_back(tags.text(1));

    Stmt links(db_, "SELECT l.feature_id, l.floor_id, l.connector FROM plan_links l "
                    "JOIN plan_features f ON f.id = l.feature_id WHERE f.floor_id = ? ORDER BY l.feature_id, l.seq");
    links.bind(1, floor_id);
    while (links.step()) p.connectors[by_id.at(links.int64(0)).index].links.push_back({links.int64(1), links.text(2)});
    return out;
}

std::optional<StoredPlan> SqlStore::plan_of_floor(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    require_exists(kind("floors"), floor_id);
    auto out = read_plan(floor_id);
    tx.commit();
    return out;
}

StoredPlan SqlStore::put_plan(std::int64_t floor_id, const plan::Plan& given, const PlanCheck& check) {
    return write([&](std::vector<Change>& changes) {
        plan::Plan plan = given;
        require_exists(kind("floors"), floor_id);
        if (check) {
            std::vector<OtherPlan> others;
            Stmt s(db_, "SELECT f.id FROM floors f JOIN buildings b ON b.id = f.building_id "
                        "WHERE b.map_id = (SELECT b2.map_id FROM floors f2 JOIN buildings b2 ON b2.id = f2.building_id "
                        "WHERE f2.id = ?1) AND f.id <> ?1 ORDER BY f.id");
            s.bind(1, floor_id);
            std::vector<std::int64_t> ids;
            while (s.step()) ids.push_back(s.int64(0));
            for (const auto id : ids) {
                auto stored = read_plan(id);
                others.push_back({id, stored ? std::optional<plan::Plan>(std::move(stored->plan)) : std::nullopt});
            }
            check(others);
        }
        // Before the old features go: they say which rooms and POIs the last version kept.
        keep_rooms(floor_id, plan, changes);
        keep_pois(floor_id, plan, changes);
        Stmt del(db_, "DELETE FROM plan_features WHERE floor_id = ?");
        del.bind(1, floor_id).run();
        Stmt head(db_, "INSERT INTO floor_plans (floor_id, version) VALUES (?, 1) ON CONFLICT (floor_id) DO UPDATE "
                       "SET version = floor_plans.version + 1, updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now')");
        head.bind(1, floor_id).run();
        write_plan_features(floor_id, plan);
        changes.insert(changes.begin(), Change{&kind("floors"), floor_id, false, true, std::nullopt, std::nullopt});
        return *read_plan(floor_id);
    });
}

std::vector<FloorWithPlan> SqlStore::plans_of_map(std::int64_t map_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);  // every floor's plan from one snapshot
    require_exists(kind("maps"), map_id);
    Stmt s(db_, "SELECT f.id, f.level FROM floor_plans fp JOIN floors f ON f.id = fp.floor_id "
                "JOIN buildings b ON b.id = f.building_id WHERE b.map_id = ? ORDER BY f.id");
    s.bind(1, map_id);
    std::vector<FloorWithPlan> out;
    while (s.step()) out.push_back({s.int64(0), s.int64(1), {}});
    for (auto& f : out) f.plan = read_plan(f.floor_id)->plan;
    tx.commit();
    return out;
}

void SqlStore::remove_plan(std::int64_t floor_id) {
    write([&](std::vector<Change>& changes) {
        require_exists(kind("floors"), floor_id);
        Stmt s(db_, "DELETE FROM floor_plans WHERE floor_id = ?");
        s.bind(1, floor_id).run();
        if (db_.changes() == 0) throw NotFound("floor " + std::to_string(floor_id) + " has no plan");
        changes.push_back(Change{&kind("floors"), floor_id, true, true, std::nullopt, std::nullopt});
    });
}

}  // namespace locus::store
