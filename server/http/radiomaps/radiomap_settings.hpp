#pragma once
// A radio map's stored matcher settings and its last tune's CV table, as JSON: what
// POST /v1/radiomaps/{id}/tune stores and answers, GET /v1/radiomaps/{id} shows, and a
// localize request falls back on (localize_request.hpp, resolve).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "locus/match/tune.hpp"
#include "store/documents.hpp"
#include "tuning/service.hpp"

namespace locus::http {

// {"algorithm": "wknn", "options": {every option a setting fixes}}
nlohmann::json settings_json(const match::Setting& setting);
// The stored text read back; empty or unreadable text gives the built-in defaults (the text
// is only ever written by settings_json, so unreadable means a damaged row).
match::Setting settings_of_text(const std::string& text);

// The CV table: {"folds", "rps", "queries", "subsampled", "chosen", "candidates": [...]}.
nlohmann::json tune_json(const match::TuneReport& report, double seconds);

// The three above as the tuning service's spelling of stored settings (tuning/service.hpp).
tuning::SettingsText settings_text();

// What GET /v1/radiomaps/{id} adds to the row: "settings" (the built-in defaults when none
// are stored, with "source": "built-in" or "tuned") and "tune" (the last tune's table; absent when never tuned).
void add_settings(nlohmann::json& radiomap, const std::optional<store::RadiomapSettings>& stored);

}  // namespace locus::http
