-- Locus schema v11: the change counter servers sharing one database watch (see
-- pg/011_change_counter.sql). A SQLite file has one server, whose changes reach its indexes
-- directly, so here the table only keeps both backends at the same schema version.
CREATE TABLE change_counter (
  id      INTEGER PRIMARY KEY CHECK (id = 1),
  version INTEGER NOT NULL
);
INSERT INTO change_counter (id, version) VALUES (1, 0);
