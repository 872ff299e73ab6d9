#include "http/localize/localize_request.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <vector>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "http/localize/plain_localize_request.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

template <typename T, typename Parse>
T parse_enum(const json& options, const std::string& where, const char* field, Parse parse, T fallback) {
    const auto s = optional_string(options, field, where, 32);
    if (!s) return fallback;
    const auto v = parse(*s);
    if (!v) throw invalid_field("'" + where + "." + std::string(field) + "' has no value \"" + *s + "\"");
    return *v;
}

}  // namespace

match::Options parse_options(const json& j, match::Options o, const std::string& where) {
    const auto bounded_int = [&](const json& options, const char* field, int lo, int hi, int fallback) {
        if (!options.contains(field)) return fallback;
        const auto& v = options.at(field);
        if (!v.is_number_integer()) throw invalid_field("'" + where + "." + std::string(field) + "' must be an integer");
        const auto n = v.get<std::int64_t>();
        if (n < lo || n > hi)
            throw ApiError(422, "out_of_range",
                           "'" + where + "." + std::string(field) + "' must be in [" + std::to_string(lo) + ", " +
                               std::to_string(hi) + "]");
        return static_cast<int>(n);
    };
    const auto bounded_number = [&](const json& options, const char* field, double lo, double hi, double fallback) {
        if (!options.contains(field)) return fallback;
        return finite_number(options, field, where, lo, hi);
    };
    if (!j.is_object()) throw invalid_field("'" + where + "' must be an object");
    only_fields(j, {"k", "tolerance", "gamma", "near", "representation", "distance", "sigma_floor", "estimate",
                          "candidates", "temperature", "offset_sigma", "bayes_k", "floor_temperature", "floor_knn",
                          "floor_knn_weight", "floor_knn_position", "floor_aps", "floor_ap_weight", "outlier_sigmas"},
                      where);
    o.k = bounded_int(j, "k", 1, 100, o.k);
    o.candidates = bounded_int(j, "candidates", 1, 100, o.candidates);
    o.tolerance = bounded_number(j, "tolerance", 0.0, 10.0, o.tolerance);
    o.gamma = bounded_number(j, "gamma", 0.0, 1000.0, o.gamma);
    o.sigma_floor = bounded_number(j, "sigma_floor", 0.1, 60.0, o.sigma_floor);
    o.temperature = bounded_number(j, "temperature", 0.01, 1000.0, o.temperature);
    o.offset_sigma = bounded_number(j, "offset_sigma", 0.0, 60.0, o.offset_sigma);
    o.outlier_sigmas = bounded_number(j, "outlier_sigmas", 0.0, 100.0, o.outlier_sigmas);
    o.bayes_k = bounded_int(j, "bayes_k", 0, 1000, o.bayes_k);
    o.floor_temperature = bounded_number(j, "floor_temperature", 0.0, 1000.0, o.floor_temperature);
    o.floor_knn = bounded_int(j, "floor_knn", 0, 100, o.floor_knn);
    o.floor_knn_weight = bounded_number(j, "floor_knn_weight", 0.0, 1.0, o.floor_knn_weight);
    if (j.contains("floor_knn_position")) {
        if (!j.at("floor_knn_position").is_boolean())
            throw invalid_field("'" + where + ".floor_knn_position' must be true or false");
        o.floor_knn_position = j.at("floor_knn_position").get<bool>();
    }
    o.floor_aps = bounded_int(j, "floor_aps", 0, 100, o.floor_aps);
    o.floor_ap_weight = bounded_number(j, "floor_ap_weight", 0.0, 1.0, o.floor_ap_weight);
    o.representation = parse_enum(j, where, "representation", match::parse_representation, o.representation);
    o.distance = parse_enum(j, where, "distance", match::parse_distance, o.distance);
    o.estimate = parse_enum(j, where, "estimate", match::parse_bayes_estimate, o.estimate);
    if (j.contains("near")) {
        const json& n = j.at("near");
        if (!n.is_object()) throw invalid_field("'" + where + ".near' must be an object {x, y, radius}");
        match::Near near;
        near.at.x = finite_number(n, "x", where + ".near");
        near.at.y = finite_number(n, "y", where + ".near");
        near.radius = finite_number(n, "radius", where + ".near", 0.0);
        if (!(near.radius > 0.0)) throw ApiError(422, "out_of_range", "'" + where + ".near.radius' must be greater than 0");
        o.near = near;
    }
    return o;
}

match::Setting resolve(const LocalizeRequest& request, const match::Setting& defaults) {
    match::Setting out;
    out.algorithm = request.algorithm_given ? request.algorithm : defaults.algorithm;
    const bool stored_base = out.algorithm == defaults.algorithm;
    if (request.options_given.is_null()) {
        out.options = stored_base ? defaults.options : request.options;
    } else {
        out.options = stored_base ? parse_options(request.options_given, defaults.options) : request.options;
    }
    return out;
}

namespace {

// The localize body is parsed in one streaming pass (nlohmann's SAX interface) straight into
// readings: a JSON tree of a 20-AP scan costs ~100 allocations and dominated the request.
// Semantic errors are remembered and thrown only once the whole body has parsed, so a body
// that is also malformed JSON is reported as such, exactly like the tree-based endpoints.
class RequestParser final : public nlohmann::json_sax<json> {
public:
    std::optional<std::string> algorithm;
    std::vector<Scan> scans;
    std::vector<Reading> means;
    bool has_scans = false, has_means = false;
    json options;  // the small "options" object, as a tree
    bool has_options = false;
    std::optional<std::int64_t> track_id;

    LocalizeRequest finish(const std::string& body) {
        reject_nul(body);
        reject_deep(body);
        const bool parsed = json::sax_parse(body, this);
        if (too_many_) throw *error_;
        if (!parsed || syntax_error_) throw ApiError(400, "invalid_json", "the request body is not valid JSON");
        if (error_) throw *error_;
        LocalizeRequest r;
        if (algorithm) {
            const auto a = match::parse_algorithm(*algorithm);
            if (!a) throw invalid_field("unknown algorithm \"" + *algorithm + "\" (bsb, nn, bsbnn, knn, wknn, bayes)");
            r.algorithm = *a;
            r.algorithm_given = true;
        }
        if (has_scans == has_means) throw invalid_field("send exactly one of 'scans' or 'measurements'");
        r.query = has_scans ? match::Query::from_scans(scans) : match::Query::from_means(means);
        if (r.query.aps.empty()) throw invalid_field("the scan holds no reading");
        if (has_options) {
            r.options = parse_options(options, {});
            r.options_given = std::move(options);
        }
        r.track_id = track_id;
        if (track_id && r.options.near) throw invalid_field("send 'track_id' (its subarea) or 'options.near', not both");
        return r;
    }

    bool null() override { return value(Kind::null); }
    bool boolean(bool b) override {
        if (in_options()) return tree_value(json(b));
        return value(Kind::other);
    }
    bool number_integer(number_integer_t v) override {
        if (depth_ == 1 && top_ == Top::track_id) return id(v > 0 ? std::optional<std::int64_t>(v) : std::nullopt);
        return number(static_cast<double>(v), json(v));
    }
    bool number_unsigned(number_unsigned_t v) override {
        if (depth_ == 1 && top_ == Top::track_id)
            return id(v > 0 && v <= static_cast<number_unsigned_t>(INT64_MAX) ? std::optional<std::int64_t>(static_cast<std::int64_t>(v)) : std::nullopt);
        return number(static_cast<double>(v), json(v));
    }
    bool number_float(number_float_t v, const string_t&) override { return number(v, json(v)); }
    bool string(string_t& v) override {
        if (in_options()) return tree_value(json(v));
        text_.assign(v);  // a copy into a reused buffer: moving would take the lexer's
        return value(Kind::text);
    }
    bool binary(binary_t&) override { return value(Kind::other); }

    bool start_object(std::size_t) override {
        ++depth_;
        if (depth_ == 1) return true;
        if (in_options()) return tree_open(json::object());
        // A reading only inside a scan array: an object at depth 4 under a misplaced object
        // would otherwise open a reading with no scan to hold it (scans.back() on an empty list).
        if (top_ == Top::scans && depth_ == 4 && scan_open_) return start_reading();
        if (top_ == Top::means && depth_ == 3) return start_reading();
        return misplaced();
    }
    bool end_object() override {
        --depth_;
        if (depth_ == 0) return true;
        if (in_options() || (top_ == Top::options && depth_ == 1)) return tree_close();
        if (reading_open_) return end_reading();
        return true;
    }
    bool start_array(std::size_t) override {
        ++depth_;
        if (in_options()) return tree_open(json::array());
        if (depth_ == 1) return not_an_object();
        if (depth_ == 2 && (top_ == Top::scans || top_ == Top::means)) return true;
        if (depth_ == 3 && top_ == Top::scans) {
            if (scans.size() >= kMaxScans) return too_many("'scans' holds more than " + std::to_string(kMaxScans) + " scans");
            scans.emplace_back();
            scan_open_ = true;
            return true;
        }
        return misplaced();
    }
    bool end_array() override {
        --depth_;
        if (in_options() || (top_ == Top::options && depth_ == 1)) return tree_close();
        if (depth_ == 2 && top_ == Top::scans) scan_open_ = false;
        if (depth_ == 1 && top_ == Top::scans && scans.empty())
            fail(invalid_field("'scans' must be a non-empty array of scans"));
        if (depth_ == 1 && top_ == Top::means && means.empty())
            fail(invalid_field("'measurements' must be a non-empty array of {bssid, rss}"));
        return true;
    }
    bool key(string_t& k) override {
        if (depth_ == 1) {
            top_ = k == "algorithm" ? Top::algorithm : k == "scans" ? Top::scans : k == "measurements" ? Top::means
                 : k == "options" ? Top::options : k == "track_id" ? Top::track_id : Top::unknown;
            has_scans = has_scans || top_ == Top::scans;
            has_means = has_means || top_ == Top::means;
            has_options = has_options || top_ == Top::options;
            if (top_ == Top::unknown) fail(invalid_field("unknown field '" + k + "'"));
            return true;
        }
        if (in_options()) {
            pending_key_.assign(k);
            return true;
        }
        field_ = k == "type" ? Field::type : k == "bssid" ? Field::bssid : k == "rss" ? Field::rss
               : k == "mean" ? Field::mean : Field::other;
        if (field_ == Field::other) field_name_.assign(k);
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        syntax_error_ = true;
        return false;
    }

private:
    enum class Top { none, algorithm, scans, means, options, track_id, unknown };
    enum class Kind { null, number, text, other };
    enum class Field { type, bssid, rss, mean, other };
    // The reading being parsed; its strings are reused from one reading to the next.
    struct Pending {
        bool has_type = false, has_bssid = false, has_rss = false;
        std::string type, bssid;
        double rss = 0.0;
    };

    bool in_options() const { return top_ == Top::options && depth_ >= 2; }

    bool number(double v, json tree) {
        if (in_options()) return tree_value(std::move(tree));
        number_ = v;
        return value(Kind::number);
    }

    bool not_an_object() {
        if (!error_) error_ = ApiError(400, "invalid_json", "the request body must be a JSON object");
        return true;
    }

    // A scalar anywhere outside "options" (a text's characters are in text_, a number in number_).
    bool value(Kind kind) {
        if (depth_ == 0) return not_an_object();
        if (in_options() || (top_ == Top::options && depth_ == 1)) {
            if (depth_ == 1) fail(invalid_field("'options' must be an object"));
            return tree_value(kind == Kind::null ? json() : json("?"));
        }
        if (depth_ == 1 && top_ == Top::track_id) return id(std::nullopt);  // not an integer
        if (depth_ == 1 && top_ == Top::algorithm) {
            if (kind != Kind::text || text_.empty() || text_.size() > 32)
                fail(invalid_field("'algorithm' must be 1 to 32 characters"));
            else algorithm = text_;
            return true;
        }
        if (!reading_open_) return misplaced();
        if (kind == Kind::null && (field_ == Field::type || field_ == Field::bssid)) return true;  // as if absent
        switch (field_) {
            case Field::type:
                if (kind != Kind::text) return fail(invalid_field("'" + where() + ".type' must be a string"));
                pending_.type.assign(text_);
                pending_.has_type = true;
                return true;
            case Field::bssid:
                if (kind != Kind::text) return fail(invalid_field("'" + where() + ".bssid' must be a string"));
                pending_.bssid.assign(text_);
                pending_.has_bssid = true;
                return true;
            case Field::mean:
                if (top_ != Top::means) break;
                [[fallthrough]];
            case Field::rss:
                if (kind != Kind::number)
                    return fail(invalid_field("'" + where() + "." + (field_ == Field::rss ? "rss" : "mean") + "' must be a number"));
                pending_.rss = number_;
                pending_.has_rss = true;
                return true;
            case Field::other:
                break;
        }
        return fail(invalid_field("unknown field '" + where() + "." + (field_ == Field::mean ? "mean" : field_name_) + "'"));
    }

    // "track_id"'s value: a positive integer, else 422 naming it.
    bool id(std::optional<std::int64_t> v) {
        if (!v) return fail(invalid_field("'track_id' must be a positive integer id"));
        track_id = v;
        return true;
    }

    bool start_reading() {
        reading_open_ = true;
        pending_.has_type = pending_.has_bssid = pending_.has_rss = false;
        return true;
    }

    bool end_reading() {
        reading_open_ = false;
        Reading r;
        if (pending_.has_type) {
            if (const char* problem = type_problem(pending_.type)) return fail(invalid_field("'" + where() + ".type' " + problem));
            r.type = pending_.type;
        }
        if (!pending_.has_bssid) return fail(invalid_field("missing field '" + where() + ".bssid'"));
        if (const char* problem = bssid_problem(pending_.bssid)) return fail(invalid_field("'" + where() + ".bssid' " + problem));
        r.bssid = pending_.bssid;  // normalised with the query (match::Query)
        if (!pending_.has_rss) return fail(invalid_field("missing field '" + where() + ".rss'"));
        if (!std::isfinite(pending_.rss)) return fail(invalid_field("'" + where() + ".rss' must be finite"));
        if (!valid_rss(pending_.rss)) return fail(out_of_range(where() + ".rss", pending_.rss, kMinRss, kMaxRss));
        r.rss = pending_.rss;
        auto& list = top_ == Top::scans ? scans.back() : means;
        if (list.size() >= kMaxReadings)
            return too_many((top_ == Top::scans ? "'scans[" + std::to_string(scans.size() - 1) + "]'" : std::string("'measurements'")) +
                            " holds more than " + std::to_string(kMaxReadings) + " readings");
        list.push_back(std::move(r));
        return true;
    }

    // Past a count limit the parse stops there: what follows is not read into memory.
    bool too_many(const std::string& message) {
        error_ = ApiError(422, "out_of_range", message);
        too_many_ = true;
        return false;
    }

    // Where the current reading sits in the body, for error messages only.
    std::string where() const {
        if (top_ == Top::scans)
            return "scans[" + std::to_string(scans.size() - 1) + "][" + std::to_string(scans.back().size()) + "]";
        return "measurements[" + std::to_string(means.size()) + "]";
    }

    bool misplaced() {
        if (top_ == Top::scans) fail(invalid_field("'scans' must be an array of scans, each an array of {type, bssid, rss}"));
        else if (top_ == Top::means) fail(invalid_field("'measurements' must be an array of {bssid, rss}"));
        else if (top_ == Top::algorithm) fail(invalid_field("'algorithm' must be a string"));
        else if (top_ == Top::options) fail(invalid_field("'options' must be an object"));
        else if (top_ == Top::track_id) fail(invalid_field("'track_id' must be a positive integer id"));
        return true;
    }

    bool fail(ApiError e) {
        if (!error_) error_ = std::move(e);
        return true;  // keep parsing: a syntax error later in the body wins
    }

    // A small tree for "options", built the way nlohmann's own DOM parser does.
    bool tree_open(json container) {
        if (stack_.empty()) {
            options = std::move(container);
            stack_.push_back(&options);
            return true;
        }
        stack_.push_back(tree_insert(std::move(container)));
        return true;
    }
    bool tree_close() {
        if (!stack_.empty()) stack_.pop_back();
        return true;
    }
    bool tree_value(json v) {
        if (stack_.empty()) return true;  // a scalar "options": already reported
        tree_insert(std::move(v));
        return true;
    }
    json* tree_insert(json v) {
        json& parent = *stack_.back();
        if (parent.is_array()) {
            parent.push_back(std::move(v));
            return &parent.back();
        }
        return &(parent[pending_key_] = std::move(v));
    }

    int depth_ = 0;
    Top top_ = Top::none;
    Field field_ = Field::other;
    std::string field_name_, pending_key_, text_;
    double number_ = 0.0;
    bool reading_open_ = false;
    bool scan_open_ = false;  // inside an array of "scans" (at depth 3), which holds readings
    Pending pending_;
    std::vector<json*> stack_;
    std::optional<ApiError> error_;
    bool syntax_error_ = false;
    bool too_many_ = false;  // a count limit stopped the parse (too_many)
};

}  // namespace

LocalizeRequest parse_localize_request(const std::string& body) {
    if (auto plain = parse_plain_localize_request(body)) return std::move(*plain);
    return parse_localize_request_in_full(body);
}

LocalizeRequest parse_localize_request_in_full(const std::string& body) {
    RequestParser parser;
    return parser.finish(body);
}

}  // namespace locus::http
