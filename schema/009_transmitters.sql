-- Locus schema v9: transmitters with known positions (WiFi APs and BLE beacons) per floor, and
-- a flag on RPs that a propagation model generated rather than a survey measured.
--
-- A transmitter is matched to a scan's readings by (type, bssid): the BSSID of an AP, or the
-- text a phone reports for a beacon (an iBeacon as "uuid:major:minor", an Eddystone beacon as
-- "namespace:instance", both lower-case hex; the API builds these from their parts). Its
-- signal follows the log-distance model
--   rss(d) = tx_power − 10·path_loss_exponent·log10(d / 1 m) − wall_attenuation·(walls crossed)
-- so tx_power is the RSS at 1 m. A floor holds one transmitter per (type, bssid): a second
-- would make ranging ambiguous.

CREATE TABLE transmitters (
  id                 INTEGER PRIMARY KEY AUTOINCREMENT,
  floor_id           INTEGER NOT NULL REFERENCES floors(id) ON DELETE CASCADE,
  name               TEXT NOT NULL DEFAULT '',
  type               TEXT NOT NULL CHECK (type IN ('wifi', 'ble')),
  bssid              TEXT NOT NULL,
  x                  REAL NOT NULL,
  y                  REAL NOT NULL,
  z                  REAL,                  -- height above the floor, m; NULL: the phone's height
  tx_power           REAL NOT NULL,         -- RSS at 1 m, dBm
  path_loss_exponent REAL NOT NULL DEFAULT 2 CHECK (path_loss_exponent > 0),
  wall_attenuation   REAL,                  -- dB per wall crossed; NULL: walls are not modelled
  UNIQUE (floor_id, type, bssid)
);

-- 1: the RP was generated from the floor's transmitters (POST /v1/floors/{id}/radiomaps/generate),
-- not measured; a survey's RPs keep 0.
ALTER TABLE rps ADD COLUMN generated INTEGER NOT NULL DEFAULT 0 CHECK (generated IN (0, 1));
