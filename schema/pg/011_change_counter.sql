-- Locus schema v11, PostgreSQL: the change counter servers sharing this database watch. Every
-- committed write that changes what a server indexes adds one to `version` in its transaction
-- (and sends NOTIFY locus_changes); each server reads it twice a second, so a write whose
-- notification it missed is still seen (store/pg_changes.hpp).
CREATE TABLE change_counter (
  id      BIGINT PRIMARY KEY CHECK (id = 1),
  version BIGINT NOT NULL
);
INSERT INTO change_counter (id, version) VALUES (1, 0);
