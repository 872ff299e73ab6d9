-- Locus schema v5, PostgreSQL: as ../005_plan_keeps_rooms.sql.
ALTER TABLE plan_features ADD COLUMN poi_id BIGINT;

CREATE INDEX plan_features_room ON plan_features(room_id) WHERE room_id IS NOT NULL;
CREATE INDEX plan_features_poi ON plan_features(poi_id) WHERE poi_id IS NOT NULL;

UPDATE plan_features SET room_id = NULL
WHERE room_id IS NOT NULL
  AND room_id NOT IN (SELECT r.id FROM rooms r WHERE r.floor_id = plan_features.floor_id);
