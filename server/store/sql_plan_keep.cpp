// A plan keeps its floor's rooms and POIs in step (Store::put_plan): run inside put_plan's
// transaction, before the old features are deleted, so a refused plan or a crash leaves every
// room and POI as it was. Rooms keep the ids clients, RPs' answers and routes already use:
// a space keeps the room it names by room_id, else the floor's room of its name.
#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "locus/plan/rects.hpp"
#include "store/sql_store.hpp"

namespace locus::store {

namespace {

std::string in_quotes(const std::string& s) { return "'" + s + "'"; }

// A POI's name as the API bounds it (kinds.cpp), which the names the plan makes must keep to.
std::size_t poi_name_max_length() {
    for (const auto& f : kind("pois").fields)
        if (f.name == "name") return f.max_length;
    return 0;
}

// A room or POI of the floor as it is before the write.
struct Existing {
    std::string name;
    bool kept_before = false;  // by the plan this PUT replaces
};

// What the writes must do for one kept row (a room or a POI).
struct Keeper {
    std::string name;
    std::optional<std::int64_t> id;  // nullopt: to be created
    std::size_t first = 0;           // the first feature (index in its list) that keeps it
    std::string label;               // that feature, as check_plan names it
};

std::string space_label(const plan::Plan& p, std::size_t i) {
    const std::string at = "spaces[" + std::to_string(i) + "]";
    return p.spaces[i].name.empty() ? at : at + " " + in_quotes(p.spaces[i].name);
}
std::string connector_label(const plan::Plan& p, std::size_t i) {
    return "connectors[" + std::to_string(i) + "] " + in_quotes(p.connectors[i].id);
}

bool same_rects(const std::vector<Rect>& a, const std::vector<Rect>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Rect& x, const Rect& y) {
        return x.xmin == y.xmin && x.ymin == y.ymin && x.xmax == y.xmax && x.ymax == y.ymax;
    });
}

// Shared by rooms and POIs: which existing row each keeper takes, then the refusals no write
// may hit later (a name held by a row the plan does not keep).
void assign(std::vector<Keeper>& keepers, const std::map<std::int64_t, Existing>& existing, bool connector,
            const char* singular, std::int64_t floor_id) {
    std::set<std::int64_t> claimed;
    for (const auto& k : keepers)
        if (k.id) claimed.insert(*k.id);
    std::map<std::string, std::int64_t, std::less<>> free_by_name;
    for (const auto& [id, e] : existing)
        if (!claimed.count(id)) free_by_name.emplace(e.name, id);
    for (auto& k : keepers) {
        if (k.id) continue;
        if (const auto it = free_by_name.find(k.name); it != free_by_name.end()) {
            k.id = it->second;
            claimed.insert(it->second);
            free_by_name.erase(it);
        }
    }
    // A kept row may take a name only if no row left as it is holds it (rows the last
    // version kept and this one does not are deleted first).
    for (const auto& k : keepers) {
        const auto it = free_by_name.find(k.name);
        if (it == free_by_name.end() || existing.at(it->second).kept_before) continue;
        throw PlanFeatureRefused(connector, k.first, k.label,
                                 std::string(singular) + " " + std::to_string(it->second) + " of floor " +
                                     std::to_string(floor_id) + " is already named " + in_quotes(k.name) + ": give " +
                                     (connector ? "this connector poi_id " : "this space room_id ") +
                                     std::to_string(it->second) + " to keep that " + singular + ", or rename one of them");
    }
}

}  // namespace

void SqlStore::keep_rooms(std::int64_t floor_id, plan::Plan& plan, std::vector<Change>& changes) {
    const Kind& rooms = kind("rooms");
    std::map<std::int64_t, Existing> existing;
    {
        Stmt s(db_, "SELECT r.id, r.name, EXISTS (SELECT 1 FROM plan_features f WHERE f.floor_id = r.floor_id "
                    "AND f.room_id = r.id) FROM rooms r WHERE r.floor_id = ?");
        s.bind(1, floor_id);
        while (s.step()) existing[s.int64(0)] = {s.text(1), s.int64(2) != 0};
    }

    // The spaces of one name keep one room; a room_id given on any of them is the group's.
    std::vector<Keeper> keepers;
    std::map<std::string, std::size_t, std::less<>> group_of_name;
    std::map<std::int64_t, std::size_t> group_of_room;
    std::vector<std::size_t> group_of_space(plan.spaces.size(), SIZE_MAX);
    std::vector<std::size_t> unnamed_with_room;
    for (std::size_t i = 0; i < plan.spaces.size(); ++i) {
        const auto& s = plan.spaces[i];
        if (s.name.empty()) {
            if (s.room_id) unnamed_with_room.push_back(i);
            continue;
        }
        auto [it, fresh] = group_of_name.emplace(s.name, keepers.size());
        if (fresh) keepers.push_back({s.name, std::nullopt, i, space_label(plan, i)});
        auto& k = keepers[it->second];
        group_of_space[i] = it->second;
        if (!s.room_id) continue;
        const auto id = *s.room_id;
        if (!existing.count(id))
            throw PlanFeatureRefused(false, i, space_label(plan, i), "room_id " + std::to_string(id) + " is not a room of floor " + std::to_string(floor_id));
        if (k.id && *k.id != id)
            throw PlanFeatureRefused(false, i, space_label(plan, i), "room_id " + std::to_string(id) + " differs from room_id " + std::to_string(*k.id) +
                                                   " of another space named " + in_quotes(s.name) +
                                                   " (the spaces of one name keep one room)");
        if (const auto other = group_of_room.find(id); other != group_of_room.end() && other->second != it->second)
            throw PlanFeatureRefused(false, i, space_label(plan, i), "room_id " + std::to_string(id) + " is also kept by the space named " +
                                                   in_quotes(keepers[other->second].name) + " (a room is kept by the spaces of one name)");
        k.id = id;
        group_of_room[id] = it->second;
    }
    // A space without a name but with a room_id is part of that room (a room drawn as several
    // polygons): it joins the spaces keeping the room, or those of the room's name, or keeps
    // the room under its own name.
    for (const auto i : unnamed_with_room) {
        const auto id = *plan.spaces[i].room_id;
        const auto room = existing.find(id);
        if (room == existing.end())
            throw PlanFeatureRefused(false, i, space_label(plan, i),
                                     "room_id " + std::to_string(id) + " is not a room of floor " + std::to_string(floor_id));
        if (const auto g = group_of_room.find(id); g != group_of_room.end()) {
            group_of_space[i] = g->second;
            continue;
        }
        const auto [it, fresh] = group_of_name.emplace(room->second.name, keepers.size());
        if (fresh) keepers.push_back({room->second.name, id, i, space_label(plan, i)});
        else if (keepers[it->second].id)
            throw PlanFeatureRefused(false, i, space_label(plan, i),
                                     "room_id " + std::to_string(id) + " is room " + in_quotes(room->second.name) +
                                         ", a name the spaces keeping room_id " + std::to_string(*keepers[it->second].id) +
                                         " give theirs");
        keepers[it->second].id = id;
        group_of_room[id] = it->second;
        group_of_space[i] = it->second;
    }
    assign(keepers, existing, false, "room", floor_id);

    std::vector<std::vector<Rect>> rects(keepers.size());
    for (std::size_t i = 0; i < plan.spaces.size(); ++i) {
        if (group_of_space[i] == SIZE_MAX) continue;
        const auto r = plan::rects_of(plan.spaces[i].shape);
        auto& into = rects[group_of_space[i]];
        into.insert(into.end(), r.begin(), r.end());
    }

    // Deletions first, then every renamed room through a name no room can have, so names may
    // move between rooms in one PUT without tripping UNIQUE (floor_id, name).
    std::set<std::int64_t> kept;
    for (const auto& k : keepers)
        if (k.id) kept.insert(*k.id);
    for (const auto& [id, e] : existing) {
        if (!e.kept_before || kept.count(id)) continue;
        changes.push_back(change_of(rooms, id, true));
        Stmt del(db_, "DELETE FROM rooms WHERE id = ?");
        del.bind(1, id).run();
    }
    Stmt rename(db_, "UPDATE rooms SET name = ? WHERE id = ?");
    for (const auto& k : keepers) {
        if (!k.id || existing.at(*k.id).name == k.name) continue;
        rename.reset();
        rename.bind(1, "\x01 plan rename " + std::to_string(*k.id)).bind(2, *k.id).run();
    }
    for (std::size_t g = 0; g < keepers.size(); ++g) {
        auto& k = keepers[g];
        if (k.id) {
            const bool renamed = existing.at(*k.id).name != k.name;
            if (renamed) {
                rename.reset();
                rename.bind(1, k.name).bind(2, *k.id).run();
            }
            if (renamed || !same_rects(rects_of(*k.id), rects[g])) {
                replace_rects(*k.id, rects[g]);
                changes.push_back(change_of(rooms, *k.id, false));
            }
        } else {
            k.id = insert_row(rooms, floor_id, Fields({{"name", k.name}}, rects[g]));
            changes.push_back(change_of(rooms, *k.id, false));
        }
    }
    for (std::size_t i = 0; i < plan.spaces.size(); ++i)
        plan.spaces[i].room_id = group_of_space[i] == SIZE_MAX ? std::nullopt : keepers[group_of_space[i]].id;
}

void SqlStore::keep_pois(std::int64_t floor_id, plan::Plan& plan, std::vector<Change>& changes) {
    const Kind& pois = kind("pois");
    struct Poi {
        std::string kind;
        double x, y;
    };
    std::map<std::int64_t, Existing> existing;
    std::map<std::int64_t, Poi> stored;
    {
        Stmt s(db_, "SELECT p.id, p.name, p.kind, p.x, p.y, EXISTS (SELECT 1 FROM plan_features f WHERE f.floor_id = "
                    "p.floor_id AND f.poi_id = p.id) FROM pois p WHERE p.floor_id = ?");
        s.bind(1, floor_id);
        while (s.step()) {
            existing[s.int64(0)] = {s.text(1), s.int64(5) != 0};
            stored[s.int64(0)] = {s.text(2), s.real(3), s.real(4)};
        }
    }

    // A connector's POI is named as the connector, or "Stairs s1" when it has no name; POI
    // names are unique on a floor, so connectors sharing a name add their id: "Lift (l2)".
    std::map<std::string, int, std::less<>> uses;
    const auto base_name = [](const plan::Connector& c) {
        if (!c.name.empty()) return c.name;
        std::string kind = plan::connector_kind_name(c.kind);
        kind[0] = static_cast<char>(kind[0] - 'a' + 'A');
        return kind + " " + c.id;
    };
    for (const auto& c : plan.connectors) ++uses[base_name(c)];
    std::vector<Keeper> keepers;
    std::set<std::string, std::less<>> names;
    std::map<std::int64_t, std::size_t> keeper_of_poi;
    for (std::size_t i = 0; i < plan.connectors.size(); ++i) {
        const auto& c = plan.connectors[i];
        std::string name = base_name(c);
        if (uses[name] > 1) name += " (" + c.id + ")";
        if (const std::size_t max = poi_name_max_length(); name.size() > max)
            throw PlanFeatureRefused(true, i, connector_label(plan, i), "its POI's name would be " + std::to_string(name.size()) +
                                                  " bytes long: POI names are at most " + std::to_string(max) +
                                                  "; shorten the connector's name");
        if (!names.insert(name).second)
            throw PlanFeatureRefused(true, i, connector_label(plan, i), "its POI would be named " + in_quotes(name) +
                                                  " as another connector's is: POI names are unique on a floor, rename one");
        if (c.poi_id) {
            if (!existing.count(*c.poi_id))
                throw PlanFeatureRefused(true, i, connector_label(plan, i), "poi_id " + std::to_string(*c.poi_id) + " is not a POI of floor " +
                                                      std::to_string(floor_id));
            if (const auto other = keeper_of_poi.find(*c.poi_id); other != keeper_of_poi.end())
                throw PlanFeatureRefused(true, i, connector_label(plan, i), "poi_id " + std::to_string(*c.poi_id) + " is also kept by connector " +
                                                      in_quotes(plan.connectors[other->second].id) + " (a POI is kept by one connector)");
            keeper_of_poi[*c.poi_id] = i;
        }
        keepers.push_back({name, c.poi_id, i, connector_label(plan, i)});
    }
    assign(keepers, existing, true, "POI", floor_id);

    std::set<std::int64_t> kept;
    for (const auto& k : keepers)
        if (k.id) kept.insert(*k.id);
    for (const auto& [id, e] : existing) {
        if (!e.kept_before || kept.count(id)) continue;
        changes.push_back(change_of(pois, id, true));
        Stmt del(db_, "DELETE FROM pois WHERE id = ?");
        del.bind(1, id).run();
    }
    Stmt rename(db_, "UPDATE pois SET name = ? WHERE id = ?");
    for (const auto& k : keepers) {
        if (!k.id || existing.at(*k.id).name == k.name) continue;
        rename.reset();
        rename.bind(1, "\x01 plan rename " + std::to_string(*k.id)).bind(2, *k.id).run();
    }
    Stmt update(db_, "UPDATE pois SET name = ?, kind = ?, x = ?, y = ? WHERE id = ?");
    for (std::size_t i = 0; i < keepers.size(); ++i) {
        auto& k = keepers[i];
        const auto& c = plan.connectors[i];
        const std::string kind = plan::connector_kind_name(c.kind);
        if (k.id) {
            const auto& was = stored.at(*k.id);
            if (existing.at(*k.id).name == k.name && was.kind == kind && was.x == c.at.x && was.y == c.at.y) continue;
            update.reset();
            update.bind(1, k.name).bind(2, kind).bind(3, c.at.x).bind(4, c.at.y).bind(5, *k.id).run();
        } else {
            k.id = insert_row(pois, floor_id, Fields{{"name", k.name}, {"kind", kind}, {"x", c.at.x}, {"y", c.at.y}});
        }
        changes.push_back(change_of(pois, *k.id, false));
    }
    for (std::size_t i = 0; i < plan.connectors.size(); ++i) plan.connectors[i].poi_id = keepers[i].id;
}

void SqlStore::refuse_if_kept(const Kind& k, std::int64_t id) {
    const bool room = k.name == "rooms";
    if (!room && k.name != "pois") return;
    Stmt s(db_, room ? "SELECT floor_id, feature, name, ident FROM plan_features WHERE room_id = ? ORDER BY seq LIMIT 1"
                     : "SELECT floor_id, feature, name, ident FROM plan_features WHERE poi_id = ? ORDER BY seq LIMIT 1");
    s.bind(1, id);
    if (!s.step()) return;
    const auto floor_id = s.int64(0);
    const std::string feature = s.text(1) + " " + in_quotes(s.text(2).empty() && !s.is_null(3) ? s.text(3) : s.text(2));
    throw KeptByPlan(std::string(k.singular) + " " + std::to_string(id) + " is kept by " + feature + " of floor " +
                         std::to_string(floor_id) + "'s plan",
                     floor_id);
}

}  // namespace locus::store
