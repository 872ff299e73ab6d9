-- Locus schema v13, PostgreSQL: as ../013_track_kalman.sql, which rebuilds the table because
-- SQLite cannot alter a CHECK; PostgreSQL replaces the constraint (named by 012's column
-- CHECK) in place.
ALTER TABLE tracks DROP CONSTRAINT tracks_fusion_check;
ALTER TABLE tracks ADD CONSTRAINT tracks_fusion_check CHECK (fusion IN ('walk_pf', 'particle', 'kalman_seed', 'kalman_ranging', 'ekf_ranging'));
ALTER TABLE tracks ADD COLUMN fusion_options TEXT;
