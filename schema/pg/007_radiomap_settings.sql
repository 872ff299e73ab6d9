-- Locus schema v7, PostgreSQL: as ../007_radiomap_settings.sql.
CREATE TABLE radiomap_settings (
  radiomap_id BIGINT PRIMARY KEY REFERENCES radiomaps(id) ON DELETE CASCADE,
  settings    TEXT NOT NULL,
  tune        TEXT NOT NULL,
  updated_at  TEXT NOT NULL DEFAULT (to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD"T"HH24:MI:SS.MS"Z"'))
);
