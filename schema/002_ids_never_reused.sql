-- Locus schema v2: an id is never handed out twice. With a plain INTEGER PRIMARY KEY SQLite
-- gives the next row max(id) + 1, so deleting the newest map, floor or RP and creating another
-- reused its id, and a client still holding the old id silently read the new object.
-- AUTOINCREMENT keeps the largest id ever used in sqlite_sequence.
--
-- SQLite cannot add AUTOINCREMENT to a column, so each table the API exposes is rebuilt
-- (https://sqlite.org/lang_altertable.html#otheralter): create the new table, copy every row with
-- its id, drop the old one, rename. migrate() runs this with PRAGMA foreign_keys=OFF (the pragma
-- is a no-op inside a transaction), so a DROP does not cascade into the children, and checks
-- PRAGMA foreign_key_check before committing. The children's REFERENCES name the parent table, so
-- they point at the new table once it has the old name. room_rects and measurements keep their
-- ids: no client ever sees them.

CREATE TABLE maps_v2 (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  name        TEXT NOT NULL UNIQUE,
  description TEXT NOT NULL DEFAULT '',
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);
INSERT INTO maps_v2 (id, name, description, created_at) SELECT id, name, description, created_at FROM maps;
DROP TABLE maps;
ALTER TABLE maps_v2 RENAME TO maps;

CREATE TABLE buildings_v2 (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id      INTEGER NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  description TEXT NOT NULL DEFAULT '',
  UNIQUE (map_id, name)
);
INSERT INTO buildings_v2 (id, map_id, name, description) SELECT id, map_id, name, description FROM buildings;
DROP TABLE buildings;
ALTER TABLE buildings_v2 RENAME TO buildings;

CREATE TABLE floors_v2 (
  id               INTEGER PRIMARY KEY AUTOINCREMENT,
  building_id      INTEGER NOT NULL REFERENCES buildings(id) ON DELETE CASCADE,
  name             TEXT NOT NULL,
  level            INTEGER NOT NULL,
  width            REAL NOT NULL CHECK (width > 0),
  height           REAL NOT NULL CHECK (height > 0),
  north_offset_deg REAL NOT NULL DEFAULT 0,
  UNIQUE (building_id, name)
);
INSERT INTO floors_v2 (id, building_id, name, level, width, height, north_offset_deg)
  SELECT id, building_id, name, level, width, height, north_offset_deg FROM floors;
DROP TABLE floors;
ALTER TABLE floors_v2 RENAME TO floors;

CREATE TABLE rooms_v2 (
  id       INTEGER PRIMARY KEY AUTOINCREMENT,
  floor_id INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name     TEXT NOT NULL,
  UNIQUE (floor_id, name)
);
INSERT INTO rooms_v2 (id, floor_id, name) SELECT id, floor_id, name FROM rooms;
DROP TABLE rooms;
ALTER TABLE rooms_v2 RENAME TO rooms;

CREATE TABLE pois_v2 (
  id       INTEGER PRIMARY KEY AUTOINCREMENT,
  floor_id INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name     TEXT NOT NULL,
  kind     TEXT NOT NULL DEFAULT '',
  x REAL NOT NULL, y REAL NOT NULL,
  UNIQUE (floor_id, name)
);
INSERT INTO pois_v2 (id, floor_id, name, kind, x, y) SELECT id, floor_id, name, kind, x, y FROM pois;
DROP TABLE pois;
ALTER TABLE pois_v2 RENAME TO pois;

CREATE TABLE radiomaps_v2 (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  floor_id    INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  description TEXT NOT NULL DEFAULT '',
  UNIQUE (floor_id, name)
);
INSERT INTO radiomaps_v2 (id, floor_id, name, description) SELECT id, floor_id, name, description FROM radiomaps;
DROP TABLE radiomaps;
ALTER TABLE radiomaps_v2 RENAME TO radiomaps;

CREATE TABLE rps_v2 (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  radiomap_id INTEGER NOT NULL REFERENCES radiomaps(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  x REAL NOT NULL, y REAL NOT NULL,
  -- Number of raw scans taken at this RP: the denominator of an AP's detection rate count/scans.
  scans       INTEGER NOT NULL DEFAULT 0 CHECK (scans >= 0),
  UNIQUE (radiomap_id, name)
);
INSERT INTO rps_v2 (id, radiomap_id, name, x, y, scans) SELECT id, radiomap_id, name, x, y, scans FROM rps;
DROP TABLE rps;
ALTER TABLE rps_v2 RENAME TO rps;
