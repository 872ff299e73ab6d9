-- Locus schema v3, PostgreSQL: as ../003_ready_probe.sql.
CREATE TABLE ready_probe (
  id     BIGINT PRIMARY KEY CHECK (id = 1),
  writes BIGINT NOT NULL DEFAULT 0
);
