#pragma once
// A floor's transmitters as the store keeps them (schema/009_transmitters.sql): what the fit,
// the generated radio maps and the ranging localize read. One listing costs one store page
// per 1000 transmitters; nothing is cached here (transmitter_cache.hpp caches for localize).
#include <cstdint>
#include <vector>

#include "store/store.hpp"

namespace locus::transmitters {

// All of a floor's transmitters, by id (NotFound for an unknown floor).
std::vector<store::Record> transmitters_of_floor(store::Store& store, std::int64_t floor_id);

}  // namespace locus::transmitters
