-- Locus schema v5: a plan keeps the floor's rooms and POIs in step with it. Each named space
-- keeps a room (plan_features.room_id, since v4) and each connector a POI (poi_id, new): a PUT
-- of the plan updates, adopts, creates or deletes them in its own transaction, and a kept room
-- or POI cannot be changed or deleted on its own. Both columns are looked up by id when a
-- room or POI is written, hence the indexes.

ALTER TABLE plan_features ADD COLUMN poi_id INTEGER;  -- a connector's API POI

CREATE INDEX plan_features_room ON plan_features(room_id) WHERE room_id IS NOT NULL;
CREATE INDEX plan_features_poi ON plan_features(poi_id) WHERE poi_id IS NOT NULL;

-- A v4 plan's room_id was the client's word: one that is not a room of the plan's own floor
-- would now make that room unchangeable, so it is dropped (the next PUT of the plan keeps a
-- room by the space's name).
UPDATE plan_features SET room_id = NULL
WHERE room_id IS NOT NULL
  AND room_id NOT IN (SELECT r.id FROM rooms r WHERE r.floor_id = plan_features.floor_id);
