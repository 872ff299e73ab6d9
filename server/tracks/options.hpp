#pragma once
// The live tracks' limits (the server's --track-* and --client-* flags, docs/tracks.md), read by
// every part of tracks::Service.
#include <cstddef>
#include <string>

namespace locus::tracks {

struct Options {
    double ttl_s = 600;            // a live track with no fix for this long closes
    double retention_s = 86'400;   // a closed track's fixes and shares are deleted this long after it closed
    double heartbeat_s = 15;       // an event stream writes a comment this often when nothing happens
    std::size_t max_streams = 100;      // open event streams, all tracks together
    std::size_t max_streams_per_track = 10;  // so one owner (or its shares) cannot take every slot
    std::size_t max_live_tracks = 10'000;
    // What one client (one address, http/front/client_address.hpp) may hold of the two caps above,
    // so it cannot fill them for everyone (docs/deploy.md "Per-client limits"). Live tracks
    // are counted in the database (its keyed hash, schema/015_track_client.sql: across
    // replicas and restarts that share `client_key`); streams by this process.
    std::size_t max_live_tracks_per_client = 100;
    std::size_t max_streams_per_client = 10;
    // The key of the clients' hashes: derived from the API key, so replicas share it and the
    // database alone does not give it; empty: a random key for this process.
    std::string client_key;
    // Tracks held at all: live, closed within the retention period, and the tombstones of
    // deleted or expired ones (kept one more retention period). Bounds what a loop of
    // anonymous open/close (or open/delete) can make the server hold. Only live tracks fill
    // it: at the cap, opening a track evicts the oldest tombstone, else the closed track that
    // closed first, so such a loop cannot lock everyone else out of opening tracks.
    std::size_t max_tracks = 50'000;
    std::size_t max_fixes_per_track = 200'000;  // more than two days at one fix a second
    std::size_t event_buffer = 64;  // fixes kept per track for a stream that falls behind (streams wake at each fix)
    std::size_t map_event_buffer = 4096;  // map-level changes kept for positions streams, all maps together
};

}  // namespace locus::tracks
