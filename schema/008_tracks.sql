-- Locus schema v8: live tracks (docs/tracks.md). A phone opens a track on a map and posts its fused
-- fixes; the owner's token and each share token are stored only as SHA-256 hashes, so the
-- database file cannot be used to follow anyone. Times are Unix seconds (REAL). A track is
-- 'live', then 'closed' (by its owner, or after --track-ttl without a fix), then 'gone' once
-- --track-retention has passed since it closed or its owner deleted it: a gone row keeps only
-- its id and token hash (so the owner is told 404 rather than 403) until another retention
-- period has passed; its fixes and shares are deleted when it goes.

CREATE TABLE tracks (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id      INTEGER REFERENCES maps(id) ON DELETE CASCADE,  -- NULL once gone
  label       TEXT,
  token_hash  BLOB NOT NULL UNIQUE,
  state       TEXT NOT NULL CHECK (state IN ('live', 'closed', 'gone')),
  created_at  REAL NOT NULL,
  last_fix_at REAL NOT NULL,  -- server clock when the last fix arrived (creation until then)
  ended_at    REAL            -- when it closed, then when it went
);

-- One fix per track and timestamp: a repeated t is a retry and keeps the first fix.
CREATE TABLE track_fixes (
  track_id    INTEGER NOT NULL REFERENCES tracks(id) ON DELETE CASCADE,
  t           REAL NOT NULL,
  floor_id    INTEGER NOT NULL,
  x           REAL NOT NULL,
  y           REAL NOT NULL,
  accuracy_m  REAL NOT NULL,
  heading_deg REAL,
  PRIMARY KEY (track_id, t)
) WITHOUT ROWID;
CREATE INDEX track_fixes_t ON track_fixes(t);

CREATE TABLE track_shares (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  track_id    INTEGER NOT NULL REFERENCES tracks(id) ON DELETE CASCADE,
  token_hash  BLOB NOT NULL UNIQUE,
  created_at  REAL NOT NULL
);
CREATE INDEX track_shares_track ON track_shares(track_id);
