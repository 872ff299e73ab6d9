#include "directory/places.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "locus/plan/ring.hpp"

namespace locus::directory {

namespace {

// A space's kind is worth searching for unless it is the default that every room has.
std::string category_of(const plan::Space& s) { return s.kind == "room" ? "" : s.kind; }

void add_tags(std::vector<std::string>& to, const std::vector<std::string>& tags) {
    for (const auto& t : tags)
        if (std::find(to.begin(), to.end(), t) == to.end()) to.push_back(t);
}

}  // namespace

MapDirectory build_directory(const std::vector<store::FloorDirectory>& floors) {
    MapDirectory out;
    for (const auto& floor : floors) {
        const auto place = [&](PlaceKind kind, std::int64_t id, std::string name, Point at) {
            Place p;
            p.kind = kind;
            p.id = id;
            p.name = std::move(name);
            p.floor_id = floor.floor_id;
            p.building_id = floor.building_id;
            p.level = floor.level;
            p.at = at;
            return p;
        };
        // Spaces kept in step with a room of this floor lend it their tags and kind.
        std::map<std::int64_t, std::vector<const plan::Space*>> linked;
        std::vector<const plan::Space*> unlinked;
        std::set<std::int64_t> rooms_here;
        for (const auto& r : floor.rooms) rooms_here.insert(r.id);
        if (floor.plan)
            for (const auto& s : floor.plan->spaces) {
                if (s.room_id && rooms_here.count(*s.room_id)) linked[*s.room_id].push_back(&s);
                else if (!s.name.empty() || !s.tags.empty()) unlinked.push_back(&s);
            }

        for (const auto& room : floor.rooms) {
            const auto spaces = linked.find(room.id);
            Place p = place(PlaceKind::room, room.id, room.name, {});
            if (spaces != linked.end())
                for (const auto* s : spaces->second) {
                    add_tags(p.tags, s->tags);
                    if (p.category.empty()) p.category = category_of(*s);
                }
            if (!room.rects.empty()) {
                p.at = room.centre();  // where POST /route starts or ends for {room_id}
            } else if (spaces != linked.end()) {
                p.at = plan::interior_point(spaces->second.front()->shape);
                p.routed_by_id = false;
            } else {
                continue;  // nowhere to show it or route to
            }
            out.places.push_back(std::move(p));
        }
        for (const auto& poi : floor.pois) {
            Place p = place(PlaceKind::poi, poi.id, poi.name, poi.at);
            p.category = poi.kind;
            out.places.push_back(std::move(p));
        }
        for (const auto* s : unlinked) {
            Place p = place(PlaceKind::space, 0, s->name, plan::interior_point(s->shape));
            p.category = category_of(*s);
            p.tags = s->tags;
            p.routed_by_id = false;
            out.places.push_back(std::move(p));
        }
    }
    std::vector<Document> docs;
    docs.reserve(out.places.size());
    for (const auto& p : out.places) docs.push_back({p.name, p.category, p.tags});
    out.index = Index(docs);
    return out;
}

}  // namespace locus::directory
