-- Locus schema v12: which filter fuses a thin client's steps on the server (`fusion` on
-- POST /v1/tracks). Stored with the track so that it survives a restart and so that every
-- server sharing a PostgreSQL database runs the one the owner chose. Tracks opened before
-- this version ran walk_pf, the default.
ALTER TABLE tracks ADD COLUMN fusion TEXT NOT NULL DEFAULT 'walk_pf' CHECK (fusion IN ('walk_pf', 'particle'));
