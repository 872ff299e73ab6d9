// The store's side of plans keeping rooms and POIs, and of plan images, on a real file: the
// change feed a plan PUT publishes, the v4 → v5 migration of client-given room_ids, and image
// bytes kept exactly (NUL bytes included) with their metadata.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "plan_fixture.hpp"
#include "store/migrations.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace store_plan_keep_test {
namespace {

using locus::store::Change;
using locus::store::Fields;
using locus::store::SqlStore;
using locus::store::kind;

using locus::testing::TempDir;

std::int64_t make_floor(SqlStore& st, const std::string& map = "M") {
    const auto m = st.create(kind("maps"), std::nullopt, {{"name", map}}).id;
    const auto b = st.create(kind("buildings"), m, {{"name", "B"}}).id;
    return st.create(kind("floors"), b, {{"name", "F"}, {"level", std::int64_t{0}}, {"width", 30.0}, {"height", 20.0}}).id;
}

locus::plan::Plan two_rooms_and_stairs() {
    locus::plan::Plan p;
    p.spaces.push_back(plan_fixture::space("Lab", plan_fixture::rect(0, 0, 5, 4)));
    p.spaces.push_back(plan_fixture::space("Office", plan_fixture::rect(5, 0, 10, 4)));
    p.connectors.push_back(plan_fixture::connector("s1", locus::plan::ConnectorKind::stairs, {9, 3}, {}));
    return p;
}

// The (kind, deleted) of each change that is not the plan's own.
std::vector<std::pair<std::string, bool>> row_changes(const std::vector<Change>& seen) {
    std::vector<std::pair<std::string, bool>> out;
    for (const auto& c : seen)
        if (!c.plan) out.emplace_back(std::string(c.kind->name), c.deleted);
    return out;
}

TEST(StorePlanKeep, APlanPutPublishesEveryRoomAndPoiItWritesAndNoOther) {
    TempDir t{"keep"};
    SqlStore st(t.path());
    const auto floor = make_floor(st);
    std::vector<Change> seen;
    st.subscribe([&](const Change& c) { seen.push_back(c); });

    const auto first = st.put_plan(floor, two_rooms_and_stairs(), nullptr);
    using V = std::vector<std::pair<std::string, bool>>;
    EXPECT_EQ(row_changes(seen), (V{{"rooms", false}, {"rooms", false}, {"pois", false}}));
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(seen.front().plan);  // the plan's own change comes first
    ASSERT_TRUE(first.plan.spaces[0].room_id && first.plan.connectors[0].poi_id);

    // The same plan again: every room and POI adopted as it is, nothing to tell.
    seen.clear();
    st.put_plan(floor, first.plan, nullptr);
    EXPECT_EQ(row_changes(seen), V{});

    // The office dropped and the stairs moved: one room deleted, one POI changed.
    auto next = first.plan;
    next.spaces.pop_back();
    next.connectors[0].at = {8, 3};
    seen.clear();
    st.put_plan(floor, next, nullptr);
    EXPECT_EQ(row_changes(seen), (V{{"rooms", true}, {"pois", false}}));
    EXPECT_EQ(st.rooms_of_floor(floor).size(), 1u);

    // A refused plan publishes nothing and changes nothing.
    auto bad = next;
    bad.spaces[0].room_id = 424242;
    seen.clear();
    try {
        st.put_plan(floor, bad, nullptr);
        ADD_FAILURE() << "a room_id of no room was taken";
    } catch (const locus::store::PlanFeatureRefused& e) {
        EXPECT_FALSE(e.connector);
        EXPECT_EQ(e.index, 0u);
        EXPECT_EQ(e.feature, "spaces[0] 'Lab'");
        EXPECT_EQ(std::string(e.what()), "room_id 424242 is not a room of floor " + std::to_string(floor));
    }
    EXPECT_TRUE(seen.empty());
    EXPECT_EQ(st.rooms_of_floor(floor).size(), 1u);

    // A kept room and POI refuse changes of their own; an ordinary one does not.
    EXPECT_THROW(st.update(kind("rooms"), *first.plan.spaces[0].room_id, {{"name", "X"}}), locus::store::KeptByPlan);
    EXPECT_THROW(st.remove(kind("pois"), *first.plan.connectors[0].poi_id), locus::store::KeptByPlan);
    st.remove_plan(floor);
    EXPECT_NO_THROW(st.update(kind("rooms"), *first.plan.spaces[0].room_id, {{"name", "X"}}));
}

TEST(StorePlanKeep, AVersion4RoomIdOfAnotherFloorIsDroppedByTheMigration) {
    TempDir t{"keep"};
    {
        locus::store::Db db(t.path());
        for (int i = 0; i < 4; ++i) db.exec(locus::server::migrations().at(static_cast<std::size_t>(i)));
        db.exec("PRAGMA user_version = 4");
        db.exec(R"sql(
            INSERT INTO maps (id, name) VALUES (1, 'M');
            INSERT INTO buildings (id, map_id, name) VALUES (1, 1, 'B');
            INSERT INTO floors (id, building_id, name, level, width, height) VALUES (1, 1, 'F0', 0, 30, 15), (2, 1, 'F1', 1, 30, 15);
            INSERT INTO rooms (id, floor_id, name) VALUES (4, 1, 'Lab'), (5, 2, 'Upstairs');
            INSERT INTO floor_plans (floor_id, version) VALUES (1, 1);
            INSERT INTO plan_features (floor_id, feature, seq, name, room_id) VALUES (1, 'space', 0, 'Lab', 4), (1, 'space', 1, 'Up', 5);
        )sql");
    }
    SqlStore st(t.path());
    const auto plan = st.plan_of_floor(1);
    ASSERT_TRUE(plan);
    ASSERT_EQ(plan->plan.spaces.size(), 2u);
    EXPECT_EQ(plan->plan.spaces[0].room_id, std::optional<std::int64_t>(4));
    EXPECT_EQ(plan->plan.spaces[1].room_id, std::nullopt);
    EXPECT_THROW(st.update(kind("rooms"), 4, {{"name", "X"}}), locus::store::KeptByPlan);
    EXPECT_NO_THROW(st.update(kind("rooms"), 5, {{"name", "Y"}}));  // another floor's room is free
}

TEST(StorePlanKeep, ImageBytesComeBackExactlyAndGoWithTheirFloor) {
    TempDir t{"keep"};
    SqlStore st(t.path());
    const auto floor = make_floor(st);
    EXPECT_FALSE(st.image_of_floor(floor));
    EXPECT_THROW(st.image_of_floor(floor + 100), locus::store::NotFound);

    std::string bytes = "\x89PNG\r\n\x1a\n";
    bytes += std::string("\0\0\0 binary \0 tail", 17);
    locus::store::FloorImage img;
    img.floor_id = floor;
    img.content_type = "image/png";
    img.width_px = 3;
    img.height_px = 2;
    img.placement = {0.5, 1.0, -2.0, 30.0};
    img.etag = "\"t1\"";
    const auto [stored, created] = st.put_image(img, bytes);
    EXPECT_TRUE(created);
    EXPECT_EQ(stored.size_bytes, static_cast<std::int64_t>(bytes.size()));
    EXPECT_EQ(stored.placement.rotation_deg, 30.0);
    EXPECT_FALSE(stored.updated_at.empty());
    const auto back = st.image_with_bytes(floor);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->second, bytes);
    EXPECT_EQ(back->first.etag, "\"t1\"");

    img.etag = "\"t2\"";
    img.placement.metres_per_pixel = 0.25;
    EXPECT_FALSE(st.put_image(img, "other").second);  // a replace
    EXPECT_EQ(st.image_of_floor(floor)->placement.metres_per_pixel, 0.25);
    EXPECT_EQ(st.image_with_bytes(floor)->second, "other");

    st.remove(kind("floors"), floor);
    EXPECT_THROW(st.image_of_floor(floor), locus::store::NotFound);
    {
        locus::store::Db db(t.path());
        locus::store::Stmt n(db, "SELECT COUNT(*) FROM floor_images");
        n.step();
        EXPECT_EQ(n.int64(0), 0);
    }
    EXPECT_THROW(st.remove_image(floor), locus::store::NotFound);
}

}  // namespace
}  // namespace store_plan_keep_test
