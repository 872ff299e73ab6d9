-- Locus schema v1: the radio-map hierarchy map -> building -> floor -> {rooms, pois, radio maps}
-- -> reference points -> measurements. Deleting a parent removes everything below it.

CREATE TABLE maps (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL UNIQUE,
  description TEXT NOT NULL DEFAULT '',
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);

CREATE TABLE buildings (
  id          INTEGER PRIMARY KEY,
  map_id      INTEGER NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  description TEXT NOT NULL DEFAULT '',
  UNIQUE (map_id, name)
);

CREATE TABLE floors (
  id               INTEGER PRIMARY KEY,
  building_id      INTEGER NOT NULL REFERENCES buildings(id) ON DELETE CASCADE,
  name             TEXT NOT NULL,
  level            INTEGER NOT NULL,
  width            REAL NOT NULL CHECK (width > 0),
  height           REAL NOT NULL CHECK (height > 0),
  north_offset_deg REAL NOT NULL DEFAULT 0,
  UNIQUE (building_id, name)
);

CREATE TABLE rooms (
  id       INTEGER PRIMARY KEY,
  floor_id INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name     TEXT NOT NULL,
  UNIQUE (floor_id, name)
);

-- An irregular room is a union of axis-aligned rectangles.
CREATE TABLE room_rects (
  id      INTEGER PRIMARY KEY,
  room_id INTEGER NOT NULL REFERENCES rooms(id) ON DELETE CASCADE,
  xmin REAL NOT NULL, ymin REAL NOT NULL, xmax REAL NOT NULL, ymax REAL NOT NULL,
  CHECK (xmin <= xmax AND ymin <= ymax)
);
CREATE INDEX room_rects_room ON room_rects(room_id);

CREATE TABLE pois (
  id       INTEGER PRIMARY KEY,
  floor_id INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name     TEXT NOT NULL,
  kind     TEXT NOT NULL DEFAULT '',
  x REAL NOT NULL, y REAL NOT NULL,
  UNIQUE (floor_id, name)
);

CREATE TABLE radiomaps (
  id          INTEGER PRIMARY KEY,
  floor_id    INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  description TEXT NOT NULL DEFAULT '',
  UNIQUE (floor_id, name)
);

CREATE TABLE rps (
  id          INTEGER PRIMARY KEY,
  radiomap_id INTEGER NOT NULL REFERENCES radiomaps(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  x REAL NOT NULL, y REAL NOT NULL,
  -- Number of raw scans taken at this RP: the denominator of an AP's detection rate count/scans.
  scans       INTEGER NOT NULL DEFAULT 0 CHECK (scans >= 0),
  UNIQUE (radiomap_id, name)
);

CREATE TABLE measurements (
  id       INTEGER PRIMARY KEY,
  rp_id    INTEGER NOT NULL REFERENCES rps(id) ON DELETE CASCADE,
  type     TEXT NOT NULL CHECK (type IN ('wifi', 'ble')),
  bssid    TEXT NOT NULL,
  mean     REAL NOT NULL,
  variance REAL NOT NULL CHECK (variance >= 0),
  count    INTEGER NOT NULL CHECK (count > 0),
  UNIQUE (rp_id, type, bssid)
);

-- Client upload ids already merged, so that a repeated upload is acknowledged and ignored.
-- Scoped per RP: a survey file's id can cover every RP it holds.
CREATE TABLE uploads (
  rp_id       INTEGER NOT NULL REFERENCES rps(id) ON DELETE CASCADE,
  upload_id   TEXT NOT NULL,
  applied_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
  PRIMARY KEY (rp_id, upload_id)
);
