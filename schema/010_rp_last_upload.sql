-- Locus schema v10: when survey scans were last merged into an RP (POST /v1/rps/{id}/scans),
-- so the viewer can show how fresh each RP's fingerprint is. ISO-8601 UTC text like the other
-- timestamps; NULL: no upload has reached the RP yet (created empty, imported or generated).
-- A repeated upload_id changes nothing, so it leaves this alone too.
ALTER TABLE rps ADD COLUMN last_upload_at TEXT;
