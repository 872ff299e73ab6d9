-- Locus schema v4: floor plans (PUT /v1/floors/{id}/plan). A plan is replaced whole, so its
-- features are rows of their floor, deleted and written again in one transaction; every point
-- is a row of its feature, so a backup of the database holds the plan exactly (no text codec
-- in between, and any SQL engine can store it the same way).

CREATE TABLE floor_plans (
  floor_id   INTEGER PRIMARY KEY REFERENCES floors(id) ON DELETE CASCADE,
  version    INTEGER NOT NULL,  -- 1 on the first PUT, +1 on each later one
  updated_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);

-- One space, wall, door or connector, in the order the plan listed it within its kind.
CREATE TABLE plan_features (
  id                INTEGER PRIMARY KEY AUTOINCREMENT,
  floor_id          INTEGER NOT NULL REFERENCES floor_plans(floor_id) ON DELETE CASCADE,
  feature           TEXT NOT NULL CHECK (feature IN ('space', 'wall', 'door', 'connector')),
  seq               INTEGER NOT NULL,
  name              TEXT NOT NULL DEFAULT '',
  kind              TEXT NOT NULL DEFAULT '',  -- a space's kind, a connector's kind
  ident             TEXT,                      -- a connector's id
  room_id           INTEGER,                   -- a space's API room
  step_free         INTEGER NOT NULL DEFAULT 0,
  seconds_per_level REAL,
  UNIQUE (floor_id, feature, seq)
);

-- A feature's points: ring 0 is a space's outer ring (holes follow) or a wall's line; a door
-- has its one or two points, a connector its one.
CREATE TABLE plan_points (
  feature_id INTEGER NOT NULL REFERENCES plan_features(id) ON DELETE CASCADE,
  ring       INTEGER NOT NULL,
  seq        INTEGER NOT NULL,
  x          REAL NOT NULL,
  y          REAL NOT NULL,
  PRIMARY KEY (feature_id, ring, seq)
) WITHOUT ROWID;

CREATE TABLE plan_tags (
  feature_id INTEGER NOT NULL REFERENCES plan_features(id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  tag        TEXT NOT NULL,
  PRIMARY KEY (feature_id, seq)
) WITHOUT ROWID;

-- A connector's links to connectors on other floors (by floor id and connector id). A link
-- to a deleted floor goes with it, so what GET answers can always be PUT again.
CREATE TABLE plan_links (
  feature_id INTEGER NOT NULL REFERENCES plan_features(id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  floor_id   INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  connector  TEXT NOT NULL,
  PRIMARY KEY (feature_id, seq)
) WITHOUT ROWID;
