#pragma once
// POST /v1/floors/{id}/radiomaps/generate and POST /v1/radiomaps/{id}/densify (radiomap_generate.cpp).
#include <httplib.h>

#include "store/store.hpp"

namespace locus::http {

void install_radiomap_generate(httplib::Server& server, store::Store& store);

}  // namespace locus::http
