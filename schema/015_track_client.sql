-- Locus schema v15: which client opened a live track, so that one client's share of the live
-- tracks (--client-live-tracks, docs/deploy.md "Per-client limits") holds across restarts and
-- across replicas sharing one database. The client's address is never stored: `client_hash`
-- is HMAC-SHA256 of its key (its address, an IPv6 one by its /64) under a key derived from the
-- server's --api-key, which the database does not hold (no API key: a random key per process,
-- so the count is then that process's). It is set only while the track is live: closing the
-- track clears it. NULL: opened with the API key (exempt), or before v15.

ALTER TABLE tracks ADD COLUMN client_hash BLOB;
CREATE INDEX tracks_live_client ON tracks(client_hash) WHERE state = 'live' AND client_hash IS NOT NULL;
