#pragma once
// A floor's place on Earth as the server answers it (`GET /v1/floors/{id}`'s `geo`, docs/geo.md),
// read into the core's georeference, for the commands that turn landmarks' lat/lon into a
// floor's metres (`locus survey walk`, `locus eval ipin`).
#include <optional>

#include <nlohmann/json.hpp>

#include "locus/geo/georeference.hpp"

namespace locus::tools {

// The floor document's `geo`; nullopt for a floor without one (`geo` null or absent).
std::optional<geo::Georeference> georeference_of(const nlohmann::json& floor);

}  // namespace locus::tools
