#pragma once
// The storage interface the services and routes use. Every call is one transaction: it either
// commits in full or changes nothing. Inputs are typed documents (documents.hpp) that the edge
// has already validated against the kind descriptors (kinds.hpp); a backend checks only what
// needs the stored data (existence, uniqueness, count bounds). SqlStore (sql_store.hpp)
// is the embedded backend.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "locus/geometry.hpp"
#include "store/documents.hpp"

namespace locus::store {

struct NotFound : std::runtime_error {
    using std::runtime_error::runtime_error;
};
struct Conflict : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// A write that would take a stored count past kMaxCount (the API answers 422 out_of_range).
struct OutOfRange : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A room or POI kept in step with a floor's plan (plan::Space::room_id, Connector::poi_id) is
// changed only through the plan: update and remove of it throw this (the API answers 409).
struct KeptByPlan : std::runtime_error {
    std::int64_t floor_id;
    KeptByPlan(const std::string& what, std::int64_t floor) : std::runtime_error(what), floor_id(floor) {}
};

// put_plan refuses a plan whose spaces or connectors cannot keep their rooms and POIs (a
// room_id of another floor, …): which feature, by its index in plan.spaces or
// plan.connectors, and named as check_plan names one ("spaces[3] 'Lab'", "connectors[0] 's1'").
struct PlanFeatureRefused : std::runtime_error {
    bool connector;
    std::size_t index;
    std::string feature;
    PlanFeatureRefused(bool is_connector, std::size_t i, std::string label, const std::string& what)
        : std::runtime_error(what), connector(is_connector), index(i), feature(std::move(label)) {}
};

// One RP as the localization index needs it, with its place in the hierarchy.
struct StoredRp {
    ReferencePoint rp;
    std::int64_t radiomap_id = 0;
    std::int64_t floor_id = 0;
    std::int64_t building_id = 0;
};

using ChangeListener = std::function<void(const Change&)>;

// One row of Store::write_rows: an update of row `id` when set, else a new row.
struct RowWrite {
    std::optional<std::int64_t> id;
    Fields fields;
};

class Store;
// Opens the database `url` names: sqlite:PATH or a plain path (created if missing), or
// postgresql://… (postgres://…). Migrates it; throws DbError when it cannot.
std::unique_ptr<Store> open(const std::string& url);

class Store {
public:
    virtual ~Store() = default;

    // Where the data lives, for logs and /ready messages.
    virtual const std::string& location() const = 0;
    // What opens the same database again (a file, or the full URL with its credentials), for
    // a service that keeps its own connection (tracks::Service). Never for logs.
    virtual const std::string& connection() const { return location(); }
    // This server in the change announcements of a database other servers share (empty
    // otherwise), for a service that writes on its own connection and announces its own
    // changes (tracks::Service, store/pg_changes.hpp).
    virtual std::string change_origin() const { return {}; }
    // Commits a one-row change, so that it has to reach durable storage: throws when the
    // database cannot really be written (GET /ready).
    virtual void probe_write() = 0;

    virtual Record create(const Kind& k, std::optional<std::int64_t> parent_id, const Fields& values) = 0;
    virtual Record get(const Kind& k, std::int64_t id) = 0;
    virtual RecordPage list(const Kind& k, std::optional<std::int64_t> parent_id, std::int64_t limit,
                            std::int64_t offset) = 0;
    virtual Record update(const Kind& k, std::int64_t id, const Fields& values) = 0;
    virtual void remove(const Kind& k, std::int64_t id) = 0;
    // Creates (under parent_id) and updates rows of `k`, in order, in ONE transaction: a
    // refused row (Conflict, NotFound, …) leaves every row as it was. Returns the written rows.
    virtual std::vector<Record> write_rows(const Kind& k, std::optional<std::int64_t> parent_id,
                                           const std::vector<RowWrite>& rows) = 0;

    virtual RpRecord rp_with_measurements(std::int64_t rp_id) = 0;
    // Welford-merges each aggregate into the RP's stored one (RssStats::merge).
    virtual UploadResult merge_scans(std::int64_t rp_id, const ScanBatch& batch) = 0;

    virtual RadioMapExport export_radiomap(std::int64_t radiomap_id) = 0;
    // The export read as it is written out: on a connection of its own, in one read
    // transaction held until the reader is dropped, so a large radio map is never whole in
    // memory and a slow client holds neither the store's lock nor the database's write lock.
    // NotFound for an unknown radio map. Needs a database another connection can open (a file
    // or PostgreSQL, as the track service does; not ":memory:").
    virtual std::unique_ptr<RadioMapReader> read_radiomap(std::int64_t radiomap_id) = 0;
    virtual ImportedRadioMap import_radiomap(std::int64_t floor_id, const RadioMapDocument& doc) = 0;
    // Adds RPs (with their measurements) to a stored radio map in one transaction; returns
    // the radio map with the counts added (POST /v1/radiomaps/{id}/densify).
    virtual ImportedRadioMap add_rps(std::int64_t radiomap_id, const std::vector<RpDocument>& rps) = 0;
    virtual Record import_map_bundle(const MapBundle& bundle) = 0;
    virtual bool has_maps() = 0;

    // The floor's plan; nullopt when it has none (NotFound when there is no such floor).
    virtual std::optional<StoredPlan> plan_of_floor(std::int64_t floor_id) = 0;
    // Replaces the floor's plan. `check` runs inside the transaction with the current plans of
    // the map's other floors (for links between floors) and may throw to refuse the plan,
    // which then writes nothing. In the same transaction the plan keeps the floor's rooms and
    // POIs in step: the spaces of each name keep one room (the given room_id, else the floor's
    // room of that name, else a new one) whose name and rectangles follow them (a space without
    // a name but with a room_id is part of that room); each connector
    // keeps a POI the same way (by poi_id, else by name); rooms and POIs the previous version
    // kept and this one does not are deleted. The stored plan holds every room_id and poi_id.
    // Throws PlanFeatureRefused when a given id is not of the floor or names clash.
    using PlanCheck = std::function<void(const std::vector<OtherPlan>& others)>;
    virtual StoredPlan put_plan(std::int64_t floor_id, const plan::Plan& plan, const PlanCheck& check) = 0;
    // NotFound when the floor has no plan. The rooms and POIs it kept stay, as ordinary ones.
    virtual void remove_plan(std::int64_t floor_id) = 0;
    // Every floor of the map that has a plan, by floor id (NotFound for an unknown map).
    virtual std::vector<FloorWithPlan> plans_of_map(std::int64_t map_id) = 0;

    // Every floor of the map (by building, level and id) with its rooms, POIs and plan, from
    // one snapshot: what the directory search indexes. NotFound for an unknown map.
    virtual std::vector<FloorDirectory> directory_of_map(std::int64_t map_id) = 0;
    // A floor's plan image (its bytes in the database, so a backup holds it). image_of_floor
    // gives the metadata only; nullopt when the floor has none (NotFound: no such floor).
    virtual std::optional<FloorImage> image_of_floor(std::int64_t floor_id) = 0;
    // The metadata and the bytes, from one snapshot.
    virtual std::optional<std::pair<FloorImage, std::string>> image_with_bytes(std::int64_t floor_id) = 0;
    // Replaces the floor's image; `image` carries what the edge read from the bytes (type,
    // size, tag) and the placement. Returns what is stored and whether there was none before.
    virtual std::pair<FloorImage, bool> put_image(const FloorImage& image, std::string_view bytes) = 0;
    // Moves, scales or turns the floor's image without sending it again: the members given
    // replace the stored ones in one transaction. NotFound when the floor has no image.
    virtual FloorImage change_placement(std::int64_t floor_id, const PlacementChange& change) = 0;
    // NotFound when the floor has no image.
    virtual void remove_image(std::int64_t floor_id) = 0;

    // A radio map's stored settings; nullopt when none were stored (NotFound: no such radio map).
    virtual std::optional<RadiomapSettings> settings_of_radiomap(std::int64_t radiomap_id) = 0;
    // Replaces them, and publishes a change of the radio map so its index follows.
    virtual RadiomapSettings put_radiomap_settings(std::int64_t radiomap_id, const RadiomapSettings& settings) = 0;
    // For the localization index. Each is a consistent snapshot.
    virtual std::vector<StoredRp> rps_of_radiomap(std::int64_t radiomap_id) = 0;
    virtual std::vector<StoredRp> rps_of_map(std::int64_t map_id) = 0;
    virtual std::vector<Room> rooms_of_floor(std::int64_t floor_id) = 0;
    virtual std::int64_t map_of_radiomap(std::int64_t radiomap_id) = 0;
    virtual std::vector<std::int64_t> radiomap_ids() = 0;

    // The change feed: `listener` is called after every committed write, on the writing
    // thread, with no transaction open (it may read the store, never subscribe). Returns the
    // token for unsubscribe, after which the listener is never called again.
    std::size_t subscribe(ChangeListener listener);
    void unsubscribe(std::size_t token);

protected:
    void publish(const std::vector<Change>& changes);

private:
    std::mutex listeners_mu_;
    std::vector<std::pair<std::size_t, ChangeListener>> listeners_;
    std::size_t next_token_ = 1;
};

}  // namespace locus::store
