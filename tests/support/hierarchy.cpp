#include "hierarchy.hpp"

#include <gtest/gtest.h>

namespace locus::testing {

namespace {
std::int64_t created_id(const Response& r, const std::string& what) {
    if (r.status != 201) {
        ADD_FAILURE() << "creating " << what << " answered " << r.status << ": " << r.raw;
        return 0;
    }
    return r.body.at("id").get<std::int64_t>();
}
}  // namespace

Hierarchy make_hierarchy(const ServerProcess& s, const std::string& map_name) {
    Hierarchy h;
    h.map = created_id(s.post("/v1/maps", {{"name", map_name}}), "map");
    h.building = created_id(s.post("/v1/maps/" + std::to_string(h.map) + "/buildings", {{"name", "Main"}}), "building");
    h.floor = created_id(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                {{"name", "Ground"}, {"level", 0}, {"width", 30.0}, {"height", 20.0}}),
                         "floor");
    h.radiomap = created_id(s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps", {{"name", "survey"}}), "radiomap");
    return h;
}

std::int64_t make_rp(const ServerProcess& s, std::int64_t radiomap, const std::string& name, double x, double y) {
    return created_id(s.post("/v1/radiomaps/" + std::to_string(radiomap) + "/rps", {{"name", name}, {"x", x}, {"y", y}}),
                      "rp " + name);
}

}  // namespace locus::testing
