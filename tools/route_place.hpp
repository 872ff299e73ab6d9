#pragma once
// A place as the command line writes it, turned into the route request's form:
//   room:12      {"room_id": 12}
//   poi:7        {"poi_id": 7}
//   3:12.5,4     {"floor_id": 3, "x": 12.5, "y": 4}
#include <string>

#include <nlohmann/json.hpp>

namespace locus::tools {

// Throws CommandError naming the option (e.g. "--from") and the forms it takes.
nlohmann::json place_json(const std::string& text, const std::string& option);

}  // namespace locus::tools
