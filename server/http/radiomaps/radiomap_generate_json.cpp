#include "http/radiomaps/radiomap_generate_json.hpp"

#include "http/crud/store_json.hpp"
#include "http/validation.hpp"
#include "locus/radio_map.hpp"
#include "store/kinds.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

transmitters::ModelOptions model_options(const json& body) {
    transmitters::ModelOptions o;
    if (body.contains("min_rss")) o.min_rss = finite_number(body, "min_rss", "", kMinRss, kMaxRss);
    if (body.contains("sigma_db")) o.sigma = finite_number(body, "sigma_db", "", 0.0, 30.0);
    if (body.contains("phone_height")) o.phone_height = finite_number(body, "phone_height", "", -10.0, 100.0);
    return o;
}

}  // namespace

transmitters::GenerateRequest parse_generate_request(const std::string& text, std::int64_t floor_id) {
    const json body = parse_object(text);
    only_fields(body, {"name", "description", "step", "min_rss", "sigma_db", "phone_height"}, "");
    transmitters::GenerateRequest r;
    r.floor_id = floor_id;
    json fields = json::object();
    for (const char* k : {"name", "description"})
        if (body.contains(k)) fields[k] = body.at(k);
    r.fields = validated_fields(store::kind("radiomaps"), fields, true);
    r.step = finite_number(body, "step", "", 0.1, 1000.0);
    r.model = model_options(body);
    return r;
}

transmitters::DensifyRequest parse_densify_request(const std::string& text, std::int64_t radiomap_id) {
    const json body = parse_object(text);
    only_fields(body, {"step", "min_rss", "sigma_db", "phone_height"}, "");
    transmitters::DensifyRequest r;
    r.radiomap_id = radiomap_id;
    r.step = finite_number(body, "step", "", 0.1, 1000.0);
    r.model = model_options(body);
    // Named for where it is, in the API's spelling of the coordinates.
    r.name_of = [](Point p) { return "dense " + json(p.x).dump() + " " + json(p.y).dump(); };
    return r;
}

ApiError grid_too_fine(const transmitters::GridTooFine& e) {
    return ApiError(422, "out_of_range",
                    "'step' = " + json(e.step).dump() + " makes " + json(e.cells).dump() +
                        (e.between_rps ? " RPs between this radio map's RPs; at most " : " RPs on this floor; at most ") +
                        std::to_string(transmitters::kMaxGeneratedRps));
}

json generated_json(const transmitters::Generated& generated) {
    json out = imported_json(generated.imported);
    out["generated"] = true;
    out["walls"] = generated.walls;
    out["transmitters"] = generated.transmitters;
    return out;
}

json densified_json(std::int64_t radiomap_id, const transmitters::Densified& densified) {
    return json{{"radiomap_id", radiomap_id},
                {"surveyed_rps", densified.surveyed_rps},
                {"added_rps", densified.added.rp_count},
                {"measurement_count", densified.added.measurement_count},
                {"transmitters", densified.transmitters},
                {"walls", densified.walls}};
}

}  // namespace locus::http
