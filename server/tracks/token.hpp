#pragma once
// Track and share tokens: 256 random bits (OpenSSL's CSPRNG), kept only as their SHA-256.
#include <string>
#include <string_view>

namespace locus::tracks {

// A new token, `prefix` followed by 64 hex digits ("trk_…" owns a track, "shr_…" reads one).
std::string new_token(std::string_view prefix);
// The 32 raw bytes of SHA-256(token): what the database and the server's memory keep.
std::string token_hash(std::string_view token);
// HMAC-SHA256 of `text` under `key` (32 raw bytes): a client's address as the database keeps
// it (schema/015_track_client.sql), which cannot be turned back without the key.
std::string keyed_hash(std::string_view key, std::string_view text);
// Equal hashes, in time independent of where they differ.
bool same_hash(std::string_view a, std::string_view b);

}  // namespace locus::tracks
