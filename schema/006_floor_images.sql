-- Locus schema v6: a floor's plan image (PUT /v1/floors/{id}/image), a scanned or exported
-- drawing to show under the plan. The bytes are a BLOB in the database, so a backup of the
-- database file holds the image with everything else. The placement says where the image lies
-- on the floor (docs in schema/openapi.yaml): pixel (u, v), u right and v down from the
-- image's top-left corner, is at floor metres
--   x = origin_x + m·u·cos θ − m·(height_px − v)·sin θ
--   y = origin_y + m·u·sin θ + m·(height_px − v)·cos θ
-- with m = metres_per_pixel and θ = rotation_deg counter-clockwise: (origin_x, origin_y) is
-- where the image's bottom-left corner lands.

CREATE TABLE floor_images (
  floor_id         INTEGER PRIMARY KEY REFERENCES floors(id) ON DELETE CASCADE,
  content_type     TEXT NOT NULL CHECK (content_type IN ('image/png', 'image/jpeg')),
  bytes            BLOB NOT NULL,
  size_bytes       INTEGER NOT NULL,  -- length(bytes), kept so metadata reads skip the blob
  width_px         INTEGER NOT NULL CHECK (width_px > 0),
  height_px        INTEGER NOT NULL CHECK (height_px > 0),
  metres_per_pixel REAL NOT NULL CHECK (metres_per_pixel > 0),
  origin_x         REAL NOT NULL DEFAULT 0,
  origin_y         REAL NOT NULL DEFAULT 0,
  rotation_deg     REAL NOT NULL DEFAULT 0,
  etag             TEXT NOT NULL,     -- of the bytes: equal bytes, equal tag
  updated_at       TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);
