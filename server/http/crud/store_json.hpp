#pragma once
// The JSON shapes of the store's typed documents (store/documents.hpp), one function each way:
// what the routes answer, and the map-bundle file the demo map is read from.
#include <nlohmann/json.hpp>

#include "store/documents.hpp"
#include "store/kinds.hpp"

namespace locus::http {

// {"id", "<parent>_id", every field (null when unset), "rects" for rooms}.
nlohmann::json record_json(const store::Kind& kind, const store::Record& record);
nlohmann::json page_json(const store::Kind& kind, const store::RecordPage& page);
nlohmann::json measurement_json(const Measurement& m);
// An RP with "measurements".
nlohmann::json rp_json(const store::RpRecord& rp);
// {"format": "locus-radiomap/1", "name", "description", "floor_id", "rps": [...]}.
nlohmann::json export_json(const store::RadioMapExport& doc);
// Its parts, for export_stream.hpp: the document with "rps" empty, and one of its RPs.
nlohmann::json export_json_without_rps(const store::Record& radiomap, const std::vector<store::Record>& floor_transmitters);
nlohmann::json export_rp_json(const store::RpDocument& rp);
// The new radio map's row with "rp_count" and "measurement_count".
nlohmann::json imported_json(const store::ImportedRadioMap& imported);

// {"map": {...}, "buildings": [{..., "floors": [{..., "rooms", "pois", "radiomaps"}]}]}, every
// level validated as its create route validates it. Throws ApiError.
store::MapBundle parse_map_bundle(const nlohmann::json& bundle);

}  // namespace locus::http
