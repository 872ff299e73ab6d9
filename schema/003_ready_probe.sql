-- Locus schema v3: GET /ready proves the database can be written by committing a change to
-- this one row (SqliteStore::probe_write); it holds nothing else.
CREATE TABLE ready_probe (
  id     INTEGER PRIMARY KEY CHECK (id = 1),
  writes INTEGER NOT NULL DEFAULT 0
);
