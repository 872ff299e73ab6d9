// The radio-map import (POST /v1/floors/{id}/radiomaps/import): parse_object,
// parse_radiomap_document, then SqlStore::import_radiomap into an in-memory SQLite
// store, as the handler in server/http/radiomaps/radiomap_routes.cpp does.
//
// Checks: validation throws nothing but http::ApiError (400/422) and the import nothing but the
// store's documented refusals (NotFound, Conflict, OutOfRange, a constraint DbError: the
// 404/409/422 answers of App::guarded); a refused document writes nothing; an accepted one
// exports a document that validates and imports again to the same export.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "http/api_error.hpp"
#include "http/json_text.hpp"
#include "http/validation.hpp"
#include "http/crud/store_json.hpp"
#include "store/sql_store.hpp"
#include "json_mutator.hpp"

using namespace locus;
using nlohmann::json;
using store::kind;

namespace {

struct Fixture {
    store::SqlStore repo{":memory:"};
    std::int64_t floor = 0, other_floor = 0;

    Fixture() {
        const auto map = repo.create(kind("maps"), std::nullopt, {{"name", "fuzz"}}).id;
        const auto building =
            repo.create(kind("buildings"), map, {{"name", "b"}}).id;
        const store::Fields floor_values = {{"name", "f0"}, {"level", 0}, {"width", 10.0}, {"height", 10.0}};
        floor = repo.create(kind("floors"), building, floor_values).id;
        store::Fields other = floor_values;
        other.values["name"] = std::string("f1");
        other_floor = repo.create(kind("floors"), building, other).id;
    }
};

Fixture& fixture() {
    static Fixture f;
    return f;
}

[[noreturn]] void fail(const std::string& what, const std::string& body) {
    std::fprintf(stderr, "fuzz_radiomap_import: %s\nbody (%zu bytes): %s\n", what.c_str(), body.size(), body.c_str());
    std::abort();
}

std::string text(const json& j) { return http::json_text(j); }

// Runs the import; returns the new radio map's row, or null when the store refused it.
json import(std::int64_t floor, const store::RadioMapDocument& doc, const std::string& body) {
    try {
        return http::imported_json(fixture().repo.import_radiomap(floor, doc));
    } catch (const store::Conflict&) {
    } catch (const store::OutOfRange&) {
    } catch (const store::DbError& e) {
        if (!e.is_constraint()) fail(std::string("a storage error (500): ") + e.what(), body);
    }
    return json();
}

void expect_empty(const std::string& when, const std::string& body) {
    if (!fixture().repo.radiomap_ids().empty()) fail("a refused document wrote a radio map (" + when + ")", body);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);
    auto& f = fixture();
    store::RadioMapDocument doc;
    try {
        doc = http::parse_radiomap_document(http::parse_object(body));
    } catch (const http::ApiError& e) {
        if (e.status != 400 && e.status != 422) fail("an ApiError with status " + std::to_string(e.status), body);
        return 0;
    }

    const json row = import(f.floor, doc, body);
    if (row.is_null()) {
        expect_empty("import", body);
        return 0;
    }
    const auto id = row.at("id").get<std::int64_t>();
    if (row.at("rp_count").get<std::size_t>() != doc.rps.size()) fail("rp_count is not the number of RPs", body);

    // What was stored exports, and the export validates and imports again to the same export.
    json exported = http::export_json(f.repo.export_radiomap(id));
    store::RadioMapDocument again;
    try {
        again = http::parse_radiomap_document(http::parse_object(http::json_text(exported)));  // as the server writes it
    } catch (const http::ApiError& e) {
        fail(std::string("the export of an accepted document does not validate: ") + e.what() + "\nexport: " + text(exported), body);
    }
    const json copy = import(f.other_floor, again, body);
    if (copy.is_null()) fail("the export of an accepted document does not import: " + text(exported), body);
    json reexported = http::export_json(f.repo.export_radiomap(copy.at("id").get<std::int64_t>()));
    exported.erase("floor_id");
    reexported.erase("floor_id");
    if (exported != reexported) fail("export, import, export changed the radio map:\n" + text(exported) + "\n" + text(reexported), body);

    f.repo.remove(kind("radiomaps"), id);
    f.repo.remove(kind("radiomaps"), copy.at("id").get<std::int64_t>());
    expect_empty("cleanup", body);
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
