-- Locus schema v7: a radio map's own matcher settings (POST /v1/radiomaps/{id}/tune stores
-- them; a localize request takes from them whatever it does not specify) and the figures of
-- the cross-validation that chose them. Both are JSON text written and read by the HTTP
-- layer only; no row: the built-in defaults.
CREATE TABLE radiomap_settings (
  radiomap_id INTEGER PRIMARY KEY REFERENCES radiomaps(id) ON DELETE CASCADE,
  settings    TEXT NOT NULL,  -- {"algorithm": ..., "options": {...}}
  tune        TEXT NOT NULL,  -- the last tune's CV table
  updated_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);
