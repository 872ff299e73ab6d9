#pragma once
// What the store takes and gives back: typed documents, parsed and validated once at the edge
// (the HTTP layer, or the demo-map file), never JSON. A second backend implements the same
// Store interface (store.hpp) over these types.
#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/plan.hpp"
#include "locus/radio_map.hpp"
#include "store/kinds.hpp"

namespace locus::store {

// One column's value; std::monostate is SQL NULL. Which alternative a field holds follows
// its Field::type (kinds.hpp): Text → string, Real → double, Integer → int64.
using Value = std::variant<std::monostate, std::string, double, std::int64_t>;

// The writable fields of one row of a Kind, by name, as a create or a patch gives them (a
// patch holds only what changes). Rooms carry their rectangles beside the columns.
struct Fields {
    std::map<std::string, Value, std::less<>> values;
    std::optional<std::vector<Rect>> rects;  // rooms only; absent: unchanged (patch) or none

    Fields() = default;
    Fields(std::initializer_list<std::pair<const std::string, Value>> init,
           std::optional<std::vector<Rect>> room_rects = std::nullopt)
        : values(init), rects(std::move(room_rects)) {}

    bool has(std::string_view name) const { return values.find(name) != values.end(); }
    // The value of a field known to be set and of type T (throws std::bad_variant_access or
    // std::out_of_range otherwise: a caller's bug, not a client's).
    template <typename T>
    const T& get(std::string_view name) const {
        const auto it = values.find(name);
        if (it == values.end()) throw std::out_of_range("no field '" + std::string(name) + "'");
        return std::get<T>(it->second);
    }
};

// A stored row: its id, its parent's id (none for maps) and every field (null ones included).
struct Record {
    std::int64_t id = 0;
    std::optional<std::int64_t> parent_id;
    Fields fields;
};

struct RecordPage {
    std::vector<Record> items;
    std::int64_t total = 0, limit = 0, offset = 0;
};

// An RP as a client reads it: the row and its per-AP aggregates, ordered by (type, bssid).
struct RpRecord {
    Record rp;
    std::vector<Measurement> measurements;
};

// POST /v1/rps/{id}/scans: aggregates to merge into one RP, each (type, bssid) once.
struct ScanBatch {
    std::optional<std::string> upload_id;   // a repeat of an applied id changes nothing
    std::vector<Measurement> measurements;  // normalised BSSIDs, counts >= 1
    std::int64_t scans = 0;                 // raw scans these measurements summarise
};

struct UploadResult {
    bool applied = false;  // false: the upload_id had been applied before; nothing changed
    RpRecord rp;           // the RP after the call
};

// The radio-map exchange document ("locus-radiomap/1"): what export gives and import takes.
struct RpDocument {
    std::string name;
    Point at;
    std::int64_t scans = 0;
    std::vector<Measurement> measurements;
    bool generated = false;  // modelled from the floor's transmitters, not measured (schema 009)
};
struct RadioMapDocument {
    Fields fields;  // the radiomap's own: name, description
    std::vector<RpDocument> rps;
    // The floor's transmitters that came with it: each is created on the target floor unless
    // the floor already has one of that (type, bssid), which is kept as stored.
    std::vector<Fields> transmitters;
};
struct RadioMapExport {
    Record radiomap;
    std::vector<RpDocument> rps;
    std::vector<Record> transmitters;  // of the radio map's floor, so the map can move with them
};
// The same, read a batch of RPs at a time, every read from one snapshot (Store::read_radiomap).
class RadioMapReader {
public:
    virtual ~RadioMapReader() = default;
    virtual const Record& radiomap() const = 0;
    virtual const std::vector<Record>& transmitters() const = 0;
    // The next (at most) `n` RPs in id order, with their measurements; empty once all were read.
    virtual std::vector<RpDocument> next_rps(std::size_t n) = 0;
};
struct ImportedRadioMap {
    Record radiomap;
    std::int64_t rp_count = 0, measurement_count = 0;
    std::int64_t transmitters_created = 0, transmitters_kept = 0;
};

// A whole map with its hierarchy (the demo map's format).
struct FloorBundle {
    Fields fields;
    std::vector<Fields> rooms, pois;
    std::vector<RadioMapDocument> radiomaps;
};
struct BuildingBundle {
    Fields fields;
    std::vector<FloorBundle> floors;
};
struct MapBundle {
    Fields fields;
    std::vector<BuildingBundle> buildings;
};

// A floor's plan as stored: replaced whole by each PUT.
struct StoredPlan {
    std::int64_t floor_id = 0;
    plan::Plan plan;
    std::int64_t version = 0;  // 1 on the first PUT, +1 on each later one
    std::string updated_at;    // ISO 8601, UTC
};

// A floor of a map with its level and its plan (floors without a plan are left out): what
// the router builds a building from.
struct FloorWithPlan {
    std::int64_t floor_id = 0;
    std::int64_t level = 0;
    plan::Plan plan;
};

// A floor of a map with what its directory lists (rooms, POIs, the plan's named and tagged
// spaces) and where the floor is.
struct FloorDirectory {
    std::int64_t floor_id = 0;
    std::int64_t building_id = 0;
    std::int64_t level = 0;
    std::vector<Room> rooms;  // by id, with their rectangles
    std::vector<Poi> pois;    // by id
    std::optional<plan::Plan> plan;
};

// Another floor of a floor's map, with its plan when it has one: what a plan's links between
// floors are checked against.
struct OtherPlan {
    std::int64_t floor_id = 0;
    std::optional<plan::Plan> plan;
};

// Where a floor's plan image lies on the floor (schema/006_floor_images.sql): pixel (u, v), u
// right and v down from the top-left corner, is at origin + R(θ)·m·(u, height_px − v), so the
// image's bottom-left corner lands on (origin_x, origin_y) and θ turns it counter-clockwise.
struct ImagePlacement {
    double metres_per_pixel = 0;
    double origin_x = 0, origin_y = 0;
    double rotation_deg = 0;
};

// A change of placement: the members given replace the stored ones (PATCH …/image/placement).
struct PlacementChange {
    std::optional<double> metres_per_pixel, origin_x, origin_y, rotation_deg;
};

// A floor's plan image without its bytes: what the placement GET answers.
struct FloorImage {
    std::int64_t floor_id = 0;
    std::string content_type;  // "image/png" or "image/jpeg"
    std::int64_t width_px = 0, height_px = 0, size_bytes = 0;
    ImagePlacement placement;
    std::string etag;        // a tag of the bytes, quoted as HTTP writes it
    std::string updated_at;  // ISO 8601, UTC
};

// A radio map's own matcher settings and the CV figures of the tune that chose them
// (schema/007_radiomap_settings.sql): JSON text the HTTP layer writes and reads, kept as given.
struct RadiomapSettings {
    std::string settings;
    std::string tune;
    std::string updated_at;  // ISO 8601, UTC
};
// Told to subscribers after each committed write (Store::subscribe), so in-memory indexes can
// follow whichever code path wrote. Where the row sits in the hierarchy is filled in for the
// kinds an index depends on (an RP: its radio map; an RP or a radio map: its map), read inside
// the write's own transaction, so a subscriber never has to read the store back.
struct Change {
    const Kind* kind = nullptr;
    std::int64_t id = 0;
    bool deleted = false;
    bool plan = false;  // the floor's plan changed (kind is floors, id the floor), not its row
    std::optional<std::int64_t> radiomap_id;
    std::optional<std::int64_t> map_id;
};

}  // namespace locus::store
