-- Locus schema v15, PostgreSQL: as ../015_track_client.sql, the hash a BYTEA.
ALTER TABLE tracks ADD COLUMN client_hash BYTEA;
CREATE INDEX tracks_live_client ON tracks(client_hash) WHERE state = 'live' AND client_hash IS NOT NULL;
