-- Locus schema v14: where a floor lies on Earth and how high it is (docs/geo.md). geo_*: the
-- WGS84 position (degrees) of floor point (geo_x, geo_y) and the bearing of the floor's +y
-- axis, clockwise from true north, in [0, 360); all five set or all NULL (the server writes
-- them together). elevation_m: height above the building's reference. NULL: unknown.
ALTER TABLE floors ADD COLUMN elevation_m REAL;
ALTER TABLE floors ADD COLUMN geo_lat REAL;
ALTER TABLE floors ADD COLUMN geo_lon REAL;
ALTER TABLE floors ADD COLUMN geo_x REAL;
ALTER TABLE floors ADD COLUMN geo_y REAL;
ALTER TABLE floors ADD COLUMN geo_bearing_deg REAL;
