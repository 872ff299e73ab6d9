// What the first search after a write to a map costs: reading the map's directory from the
// store (Store::directory_of_map, SQLite in memory) and building its places and index
// (directory::build_directory), for a map of 20 floors with 400 rooms (rectangles, and a plan
// whose 400 spaces are linked to them, a third tagged with a person) and 100 POIs each:
// 10,000 names. Run by hand:
//   build/bin/directory_rebuild_bench
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "directory/places.hpp"
#include "store/sql_store.hpp"

namespace {

using namespace locus;

constexpr int kFloors = 20, kRooms = 400, kPois = 100;

struct Campus {
    store::SqlStore db{":memory:"};
    std::int64_t map = 0;
};

Campus& campus() {
    static const std::unique_ptr<Campus> c = [] {
        auto out = std::make_unique<Campus>();
        store::MapBundle bundle;
        bundle.fields = {{"name", "Campus"}};
        store::BuildingBundle building;
        building.fields = {{"name", "Main"}};
        for (int f = 0; f < kFloors; ++f) {
            store::FloorBundle floor;
            floor.fields = {{"name", "Floor " + std::to_string(f)}, {"level", std::int64_t{f}}, {"width", 200.0}, {"height", 20.0}};
            for (int r = 0; r < kRooms; ++r) {
                const double x = (r % 100) * 2.0, y = (r / 100) * 5.0;
                floor.rooms.push_back(store::Fields({{"name", "Room " + std::to_string(f) + "." + std::to_string(r)}},
                                                    std::vector<Rect>{{x, y, x + 2.0, y + 5.0}}));
            }
            for (int p = 0; p < kPois; ++p)
                floor.pois.push_back({{"name", "Printer " + std::to_string(p)}, {"kind", "printer"}, {"x", 1.0 + p}, {"y", 1.0}});
            building.floors.push_back(std::move(floor));
        }
        bundle.buildings.push_back(std::move(building));
        out->map = out->db.import_map_bundle(bundle).id;
        const char* people[] = {"Anna Müller", "José Núñez", "Dr. Rossi", "Søren Håkansson", "Zoë Brontë"};
        for (const auto& floor : out->db.directory_of_map(out->map)) {
            plan::Plan p;
            for (std::size_t i = 0; i < floor.rooms.size(); ++i) {
                const Rect& r = floor.rooms[i].rects.front();
                plan::Space s;
                s.name = floor.rooms[i].name;
                s.kind = "office";
                if (i % 3 == 0) s.tags.push_back(people[i % 5]);
                s.shape.outer = {{r.xmin, r.ymin}, {r.xmax, r.ymin}, {r.xmax, r.ymax}, {r.xmin, r.ymax}, {r.xmin, r.ymin}};
                s.room_id = floor.rooms[i].id;
                p.spaces.push_back(std::move(s));
            }
            out->db.put_plan(floor.floor_id, p, {});
        }
        return out;
    }();
    return *c;
}

void BM_ReadDirectory(benchmark::State& state) {
    Campus& c = campus();
    for (auto _ : state) benchmark::DoNotOptimize(c.db.directory_of_map(c.map));
}
BENCHMARK(BM_ReadDirectory)->Unit(benchmark::kMillisecond);

void BM_BuildDirectory(benchmark::State& state) {
    Campus& c = campus();
    const auto floors = c.db.directory_of_map(c.map);
    std::size_t places = 0;
    for (auto _ : state) {
        const auto d = directory::build_directory(floors);
        places = d.places.size();
        benchmark::DoNotOptimize(d);
    }
    state.counters["places"] = static_cast<double>(places);
}
BENCHMARK(BM_BuildDirectory)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
