#pragma once
// POST /v1/floors/{id}/transmitters/fit: each AP heard in the floor's surveyed RPs gets its
// log-distance model fitted (ranging/fit.hpp): tx power and exponent at its stored position,
// or the position too when the floor has no transmitter of that id (or `refit_positions`).
// ?apply=true stores the fits (known transmitters updated, new ones created).
#include <httplib.h>

#include "store/store.hpp"

namespace locus::http {

void install_transmitter_fit(httplib::Server& server, store::Store& store);

}  // namespace locus::http
