-- Locus schema v5: a plan keeps the floor's rooms and POIs in step with it. Each named space
-- keeps a room (plan_features.room_id, since v4) and each connector a POI (poi_id, new): a PUT
-- of the plan updates, adopts, creates or deletes them in its own transaction, and a kept room
-- or POI cannot be changed or deleted on its own. Both columns are looked up by id when a
-- room or POI is written, hence the indexes.

ALTER TABLE plan_features ADD COLUMN poi_id INTEGER;  -- a connector's API POI

CREATE INDEX plan_features_room ON plan_features(room_id) WHERE room_id IS NOT NULL;
CREATE INDEX plan_features_poi ON plan_features(poi_id) WHERE poi_id IS NOT NULL;
