-- Locus schema v6, PostgreSQL: a floor's plan image, as ../006_floor_images.sql (BYTEA for BLOB).
CREATE TABLE floor_images (
  floor_id         BIGINT PRIMARY KEY REFERENCES floors(id) ON DELETE CASCADE,
  content_type     TEXT NOT NULL CHECK (content_type IN ('image/png', 'image/jpeg')),
  bytes            BYTEA NOT NULL,
  size_bytes       BIGINT NOT NULL,
  width_px         BIGINT NOT NULL CHECK (width_px > 0),
  height_px        BIGINT NOT NULL CHECK (height_px > 0),
  metres_per_pixel DOUBLE PRECISION NOT NULL CHECK (metres_per_pixel > 0),
  origin_x         DOUBLE PRECISION NOT NULL DEFAULT 0,
  origin_y         DOUBLE PRECISION NOT NULL DEFAULT 0,
  rotation_deg     DOUBLE PRECISION NOT NULL DEFAULT 0,
  etag             TEXT NOT NULL,
  updated_at       TEXT NOT NULL DEFAULT (to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD"T"HH24:MI:SS.MS"Z"'))
);
