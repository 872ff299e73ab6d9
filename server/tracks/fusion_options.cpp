#include "tracks/fusion_options.hpp"

#include <nlohmann/json.hpp>

namespace locus::tracks {

bool FusionOptions::empty() const {
    for (const auto& spec : kFusionOptions)
        if (this->*spec.field) return false;
    return !subarea;
}

nlohmann::json fusion_options_json(const FusionOptions& o) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& spec : kFusionOptions)
        if (const auto& v = o.*spec.field) j[spec.name] = *v;
    if (o.subarea) j[kSubareaOption] = *o.subarea;
    return j;
}

std::string fusion_options_text(const FusionOptions& o) { return o.empty() ? "" : fusion_options_json(o).dump(); }

FusionOptions fusion_options_of_text(const std::string& text) {
    FusionOptions o;
    if (text.empty()) return o;
    const auto j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_object()) return o;  // written by fusion_options_text only: not expected
    for (const auto& spec : kFusionOptions)
        if (const auto it = j.find(spec.name); it != j.end() && it->is_number()) o.*spec.field = it->get<double>();
    if (const auto it = j.find(kSubareaOption); it != j.end() && it->is_boolean()) o.subarea = it->get<bool>();
    return o;
}

}  // namespace locus::tracks
