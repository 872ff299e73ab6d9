#pragma once
// A transmitter's body (POST/PATCH /v1/floors/{id}/transmitters, /v1/transmitters/{id}) checked
// beyond what each field's descriptor says: the type, the id's form (a BSSID, or an iBeacon's
// or Eddystone beacon's parts), and the position within the floor.
#include <nlohmann/json.hpp>

#include "store/documents.hpp"
#include "store/store.hpp"

namespace locus::http {

// The writable fields of a create (everything required present) or a patch. "ibeacon":
// {"uuid", "major", "minor"} and "eddystone": {"namespace", "instance"} are accepted in place of
// "bssid" and written as the text a phone reports for them (schema/009_transmitters.sql),
// with "type" "ble". Throws ApiError 422 naming the field.
store::Fields transmitter_fields(const nlohmann::json& body, bool create);

// 422 out_of_floor unless (x, y) lies on the floor, [0, width] × [0, height] (docs/spec.md §2.1).
void check_on_floor(const store::Record& floor, double x, double y);

}  // namespace locus::http
