#pragma once
// POST /v1/floors/{id}/transmitters/fit: the route of transmitters::fit_transmitters
// (transmitters/fit.hpp), which fits each AP heard in the floor's survey; ?apply=true stores
// the fits. Its JSON is http/transmitter_fit_json.hpp.
#include <httplib.h>

#include "store/store.hpp"

namespace locus::http {

void install_transmitter_fit(httplib::Server& server, store::Store& store);

}  // namespace locus::http
