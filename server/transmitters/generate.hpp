#pragma once
// Radio maps modelled from a floor's transmitters and its plan's walls (ranging/propagation.hpp),
// each RP a grid point marked generated, each AP's mean the multi-wall model's RSS and its
// variance sigma_db² (the shadowing a fit leaves, e.g. fit.hpp's residual_db):
// generate_radiomap makes a new radio map with no survey; densify_radiomap fills a sparse survey
// between its RPs. POST /v1/floors/{id}/radiomaps/generate and POST /v1/radiomaps/{id}/densify
// are their HTTP face (http/radiomaps/radiomap_generate.cpp).
//
// Cost: one read of the floor's transmitters and plan, then per grid point the model's RSS of
// every transmitter (walls crossed found through a grid index of the plan's segments; densify
// also compares each point with every stored RP), and one write transaction. A grid of more
// than kMaxGeneratedRps points is refused before anything is modelled.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "locus/geometry.hpp"
#include "store/documents.hpp"
#include "store/store.hpp"

namespace locus::transmitters {

// A grid finer than this many RPs is refused: one request must stay one bounded transaction.
inline constexpr std::size_t kMaxGeneratedRps = 100'000;

// Model parameters shared by generate and densify.
struct ModelOptions {
    double min_rss = -95.0;     // an AP modelled weaker is not heard
    double sigma = 4.0;         // dB, the modelled shadowing
    double phone_height = 1.2;  // m, against a transmitter's z
};

struct GenerateRequest {
    std::int64_t floor_id = 0;
    store::Fields fields;  // the new radio map's name and description, validated
    double step = 1.0;     // m between grid points
    ModelOptions model;
};

struct DensifyRequest {
    std::int64_t radiomap_id = 0;
    double step = 1.0;
    ModelOptions model;
    // The name of an added RP at a point; the API spells its coordinates (http/ writes them
    // as JSON numbers), so this layer takes the spelling from it.
    std::function<std::string(Point)> name_of;
};

struct Modelled {
    std::size_t transmitters = 0, walls = 0;  // what the model was built from
};

struct Generated : Modelled {
    store::ImportedRadioMap imported;
};

struct Densified : Modelled {
    std::size_t surveyed_rps = 0;      // the radio map's RPs before
    store::ImportedRadioMap added;     // the radio map, with the RPs and measurements added
};

// `step` would make `cells` RPs, more than kMaxGeneratedRps (the API answers 422 out_of_range).
struct GridTooFine : std::runtime_error {
    double step, cells;
    bool between_rps;  // densify's grid (between a radio map's RPs), else a floor's
    GridTooFine(double s, double c, bool between)
        : std::runtime_error("grid too fine"), step(s), cells(c), between_rps(between) {}
};

// NotFound for an unknown floor; GridTooFine; Refused `no_transmitters` for a floor without any.
Generated generate_radiomap(store::Store& store, const GenerateRequest& request);
// NotFound for an unknown radio map; Refused `too_few_rps` below 2 RPs; GridTooFine; Refused
// `no_transmitters`. Only grid points at least step/2 from every stored RP are added.
Densified densify_radiomap(store::Store& store, const DensifyRequest& request);

}  // namespace locus::transmitters
