// A map's directory in one read transaction: four plain queries over the map's floors (rooms,
// their rectangles, POIs) and each floor's plan, so the index never mixes two versions.
#include <map>

#include "store/sql_store.hpp"

namespace locus::store {

std::vector<FloorDirectory> SqlStore::directory_of_map(std::int64_t map_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    require_exists(kind("maps"), map_id);
    std::vector<FloorDirectory> out;
    std::map<std::int64_t, std::size_t> floor_at;
    Stmt floors(db_, "SELECT f.id, f.building_id, f.level FROM floors f JOIN buildings b ON b.id = f.building_id "
                     "WHERE b.map_id = ? ORDER BY f.building_id, f.level, f.id");
    floors.bind(1, map_id);
    while (floors.step()) {
        floor_at[floors.int64(0)] = out.size();
        out.push_back({floors.int64(0), floors.int64(1), floors.int64(2), {}, {}, std::nullopt});
    }
    const std::string of_map = " JOIN floors f ON f.id = t.floor_id JOIN buildings b ON b.id = f.building_id WHERE b.map_id = ?";

    std::map<std::int64_t, std::pair<std::size_t, std::size_t>> room_at;  // room id → (floor, index)
    Stmt rooms(db_, "SELECT t.id, t.floor_id, t.name FROM rooms t" + of_map + " ORDER BY t.id");
    rooms.bind(1, map_id);
    while (rooms.step()) {
        auto& floor = out[floor_at.at(rooms.int64(1))];
        room_at[rooms.int64(0)] = {floor_at.at(rooms.int64(1)), floor.rooms.size()};
        floor.rooms.push_back({rooms.int64(0), rooms.text(2), {}});
    }
    Stmt rects(db_, "SELECT r.room_id, r.xmin, r.ymin, r.xmax, r.ymax FROM room_rects r JOIN rooms t ON t.id = r.room_id" +
                        of_map + " ORDER BY r.id");
    rects.bind(1, map_id);
    while (rects.step()) {
        const auto [f, i] = room_at.at(rects.int64(0));
        out[f].rooms[i].rects.push_back({rects.real(1), rects.real(2), rects.real(3), rects.real(4)});
    }
    Stmt pois(db_, "SELECT t.id, t.floor_id, t.name, t.kind, t.x, t.y FROM pois t" + of_map + " ORDER BY t.id");
    pois.bind(1, map_id);
    while (pois.step())
        out[floor_at.at(pois.int64(1))].pois.push_back({pois.int64(0), pois.text(2), pois.text(3), {pois.real(4), pois.real(5)}});

    for (auto& floor : out)
        if (auto stored = read_plan(floor.floor_id)) floor.plan = std::move(stored->plan);
    tx.commit();
    return out;
}

}  // namespace locus::store
