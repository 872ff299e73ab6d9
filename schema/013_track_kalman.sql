-- Locus schema v13: a track may be fused by the Kalman filters of the Kalman-fusion paper
-- (docs/spec.md §8; `fusion` 'kalman_seed', the stored name of POST /v1/tracks's
-- kalman_trilateration, or 'kalman_ranging') or our tightly coupled ranging filter
-- ('ekf_ranging'; added before 013 was released, so no database has 013 without it), with their noise options
-- (`fusion_options`, JSON text; NULL: the method's defaults). Tracks opened before keep their
-- fusion and have no options.
--
-- SQLite cannot alter a CHECK, so tracks is rebuilt as 002_ids_never_reused.sql rebuilt its
-- tables (https://sqlite.org/lang_altertable.html#otheralter): create, copy every row with its
-- id, drop, rename. migrate() runs it with foreign keys off and checks foreign_key_check before
-- committing; track_fixes and track_shares name `tracks`, so they point at the new table once it
-- has the name. The largest id ever handed out is carried over, so ids are still never reused.

CREATE TABLE tracks_v13 (
  id             INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id         INTEGER REFERENCES maps(id) ON DELETE CASCADE,  -- NULL once gone
  label          TEXT,
  token_hash     BLOB NOT NULL UNIQUE,
  state          TEXT NOT NULL CHECK (state IN ('live', 'closed', 'gone')),
  created_at     REAL NOT NULL,
  last_fix_at    REAL NOT NULL,  -- server clock when the last fix arrived (creation until then)
  ended_at       REAL,           -- when it closed, then when it went
  fusion         TEXT NOT NULL DEFAULT 'walk_pf' CHECK (fusion IN ('walk_pf', 'particle', 'kalman_seed', 'kalman_ranging', 'ekf_ranging')),
  fusion_options TEXT
);
INSERT INTO tracks_v13 (id, map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion)
  SELECT id, map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion FROM tracks;
-- The copy made a sequence row for tracks_v13 at its largest id; a deleted newer track may have
-- taken a larger one.
UPDATE sqlite_sequence SET seq = max(seq, coalesce((SELECT seq FROM sqlite_sequence WHERE name = 'tracks'), 0))
  WHERE name = 'tracks_v13';
INSERT INTO sqlite_sequence (name, seq)
  SELECT 'tracks_v13', seq FROM sqlite_sequence WHERE name = 'tracks'
  AND NOT EXISTS (SELECT 1 FROM sqlite_sequence WHERE name = 'tracks_v13');
DROP TABLE tracks;
ALTER TABLE tracks_v13 RENAME TO tracks;
