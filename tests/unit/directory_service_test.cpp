// What a map's directory lists (directory/places.cpp) and how long the service keeps it
// (directory/service.cpp), on a real SqlStore in memory.
#include <gtest/gtest.h>

#include <algorithm>

#include "directory/service.hpp"
#include "store/sql_store.hpp"

namespace directory_service_test {
namespace {

using namespace locus;
using locus::store::kind;

plan::Space space(std::string name, std::vector<std::string> tags, double x0, double x1, std::optional<std::int64_t> room = {},
                  std::string space_kind = "room") {
    plan::Space s;
    s.name = std::move(name);
    s.kind = std::move(space_kind);
    s.tags = std::move(tags);
    s.shape.outer = {{x0, 0}, {x1, 0}, {x1, 4}, {x0, 4}, {x0, 0}};
    s.room_id = room;
    return s;
}

const directory::Place* named(const directory::MapDirectory& d, const std::string& name) {
    const auto it = std::find_if(d.places.begin(), d.places.end(), [&](const auto& p) { return p.name == name; });
    return it == d.places.end() ? nullptr : &*it;
}

struct Site {
    store::SqlStore db{":memory:"};
    std::int64_t map = 0, building = 0, floor = 0, other_floor = 0;
    Site() {
        map = db.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
        building = db.create(kind("buildings"), map, {{"name", "B"}}).id;
        floor = db.create(kind("floors"), building, {{"name", "F"}, {"level", 2}, {"width", 50.0}, {"height", 4.0}}).id;
        other_floor = db.create(kind("floors"), building, {{"name", "G"}, {"level", 0}, {"width", 50.0}, {"height", 4.0}}).id;
    }
    std::int64_t room(std::int64_t on, const std::string& name, std::vector<Rect> rects) {
        return db.create(kind("rooms"), on, store::Fields({{"name", name}}, std::move(rects))).id;
    }
};

TEST(DirectoryPlaces, RoomsTakeTheirSpacesTagsAndUnlinkedSpacesStandAlone) {
    Site s;
    const auto office = s.room(s.floor, "Office 12", {{0, 0, 10, 4}});
    const auto elsewhere = s.room(s.other_floor, "Store", {{0, 0, 2, 2}});
    s.db.create(kind("pois"), s.floor, {{"name", "Printer"}, {"kind", "printer"}, {"x", 12.0}, {"y", 1.0}});
    plan::Plan p;
    // Every named space keeps a room of its floor (Store::put_plan): the café and the annex
    // get rooms of their own; a nameless space is found by its tags alone.
    p.spaces = {space("Office 12", {"Dr. Rossi"}, 0, 10, office, "office"),
                space("", {"Anna Müller"}, 0, 10, office),         // a second space of the same room
                space("Café", {}, 10, 20, std::nullopt, "cafeteria"),
                space("", {}, 20, 30),                               // nothing to find it by
                space("Annex", {}, 30, 40),
                space("", {"Reception desk"}, 40, 50)};
    s.db.put_plan(s.floor, p, {});
    const auto d = directory::build_directory(s.db.directory_of_map(s.map));

    ASSERT_EQ(d.places.size(), 6u);  // Office 12, Café, Annex, Printer, the desk; Store
    EXPECT_EQ(d.index.size(), d.places.size());
    const auto* room = named(d, "Office 12");
    ASSERT_NE(room, nullptr);
    EXPECT_EQ(room->kind, directory::PlaceKind::room);
    EXPECT_EQ(room->id, office);
    EXPECT_EQ(room->tags, (std::vector<std::string>{"Dr. Rossi", "Anna Müller"}));
    EXPECT_EQ(room->category, "office");
    EXPECT_EQ(room->level, 2);
    EXPECT_EQ(room->building_id, s.building);
    EXPECT_DOUBLE_EQ(room->at.x, 5.0);
    EXPECT_TRUE(room->routed_by_id);
    const auto* cafe = named(d, "Café");
    ASSERT_NE(cafe, nullptr);
    EXPECT_EQ(cafe->kind, directory::PlaceKind::room);
    EXPECT_EQ(cafe->category, "cafeteria");
    EXPECT_TRUE(cafe->routed_by_id);
    EXPECT_DOUBLE_EQ(cafe->at.x, 15.0);
    ASSERT_NE(named(d, "Annex"), nullptr);
    EXPECT_EQ(named(d, "Annex")->kind, directory::PlaceKind::room);
    const auto* desk = named(d, "");
    ASSERT_NE(desk, nullptr);
    EXPECT_EQ(desk->kind, directory::PlaceKind::space);
    EXPECT_EQ(desk->tags, std::vector<std::string>{"Reception desk"});
    EXPECT_FALSE(desk->routed_by_id);
    EXPECT_DOUBLE_EQ(desk->at.x, 45.0);
    EXPECT_EQ(named(d, "Store")->tags, std::vector<std::string>{});  // another floor's: no plan links it
    (void)elsewhere;
    EXPECT_EQ(named(d, "Printer")->category, "printer");

    // The index is built over the same places in the same order.
    const auto hits = d.index.search("muller", 10);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(d.places[hits[0].document].id, office);
}

TEST(DirectoryPlaces, ARoomWithoutRectanglesIsFoundAtItsSpaceOrNotAtAll) {
    Site s;
    const auto linked = s.room(s.floor, "Lab", {{20, 0, 30, 4}});
    const auto bare = s.room(s.floor, "Nowhere", {{40, 0, 45, 4}});
    s.db.update(kind("rooms"), linked, store::Fields({}, std::vector<Rect>{}));
    s.db.update(kind("rooms"), bare, store::Fields({}, std::vector<Rect>{}));
    plan::Plan p;
    p.spaces = {space("Lab", {}, 0, 10, linked)};
    s.db.put_plan(s.floor, p, {});
    const auto d = directory::build_directory(s.db.directory_of_map(s.map));
    ASSERT_EQ(d.places.size(), 1u);  // the bare room has nowhere to be found
    EXPECT_EQ(d.places[0].id, linked);
    // The plan gave the linked room its space's rectangles: found there, and routable by id.
    EXPECT_TRUE(d.places[0].routed_by_id);
    EXPECT_DOUBLE_EQ(d.places[0].at.x, 5.0);

    // A room with no rectangles of its own and a space elsewhere is found at the space, for
    // {floor_id, x, y} only: a plan of another floor cannot make such a room any more, so the
    // store is given one directly.
    s.db.remove_plan(s.floor);
    s.db.update(kind("rooms"), linked, store::Fields({}, std::vector<Rect>{}));
    auto floors = s.db.directory_of_map(s.map);
    for (auto& f : floors)
        if (f.floor_id == s.floor) f.plan = p;
    const auto d2 = directory::build_directory(floors);
    ASSERT_EQ(d2.places.size(), 1u);
    EXPECT_FALSE(d2.places[0].routed_by_id);  // {floor_id, x, y}: /route cannot take this room
    EXPECT_DOUBLE_EQ(d2.places[0].at.x, 5.0);
}

TEST(DirectoryService, AnIndexIsKeptUntilWhatItListsChanges) {
    Site s;
    const auto office = s.room(s.floor, "Office", {{0, 0, 10, 4}});
    directory::Service service(s.db);
    const auto first = service.of_map(s.map);
    ASSERT_EQ(first->places.size(), 1u);
    EXPECT_EQ(service.of_map(s.map), first);  // kept

    // Radio maps and scans are not in the directory.
    const auto radiomap = s.db.create(kind("radiomaps"), s.floor, {{"name", "R"}}).id;
    s.db.create(kind("rps"), radiomap, {{"name", "p"}, {"x", 1.0}, {"y", 1.0}});
    EXPECT_EQ(service.of_map(s.map), first);

    s.db.update(kind("rooms"), office, {{"name", "Library"}});
    const auto renamed = service.of_map(s.map);
    EXPECT_NE(renamed, first);
    EXPECT_EQ(renamed->places.at(0).name, "Library");

    s.db.create(kind("pois"), s.floor, {{"name", "Exit"}, {"x", 1.0}, {"y", 1.0}});
    EXPECT_EQ(service.of_map(s.map)->places.size(), 2u);

    plan::Plan p;
    p.spaces = {space("Office", {"Dr. Rossi"}, 0, 10, office)};
    s.db.put_plan(s.floor, p, {});
    EXPECT_EQ(service.of_map(s.map)->index.search("rossi", 10).size(), 1u);

    s.db.update(kind("floors"), s.floor, {{"level", 7}});
    EXPECT_EQ(service.of_map(s.map)->places.at(0).level, 7);

    s.db.remove(kind("floors"), s.floor);
    EXPECT_TRUE(service.of_map(s.map)->places.empty());
    EXPECT_THROW(service.of_map(999), store::NotFound);
}

}  // namespace
}  // namespace directory_service_test
