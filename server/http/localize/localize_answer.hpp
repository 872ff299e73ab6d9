#pragma once
// The localize answer's JSON text, written directly from a match result.
#include <string>

#include "http/places_json.hpp"
#include "http/plans/floor_geo.hpp"
#include "http/localize/localize_request.hpp"
#include "localize/service.hpp"

namespace locus::http {

// Matches the request on the snapshot's index and writes the answer, with the estimate's
// "lat"/"lon" when `geo` knows its floor's georeference, and the POIs near it ("nearby")
// from `places` (always present: [] without it). Throws ApiError 422 no_match when no RP
// shares an AP with the scan.
std::string answer(const localize::Snapshot& snapshot, const LocalizeRequest& request, FloorGeoCache* geo = nullptr,
                   floors::FloorPlacesCache* places = nullptr);

// Fills snapshot.candidate_json from its index, so an answer writes only each candidate's
// score and matched APs: formatting the ten candidates' coordinates and ids anew was a quarter
// of a one-floor localize request's own work. An answer without it writes every field.
// localize::Service calls it (as its Prepare hook) on each snapshot it builds.
void prepare_answers(localize::Snapshot& snapshot);

}  // namespace locus::http
