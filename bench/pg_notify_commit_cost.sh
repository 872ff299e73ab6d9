#!/usr/bin/env bash
# What a NOTIFY in each fix post costs PostgreSQL's commit throughput (docs/deploy.md, "Live
# tracks"): pgbench runs a fix post's writes (insert a fix, update the track's last_fix_at), one
# track per client, with and without the locus_tracks NOTIFY, on a throwaway cluster with fsync
# and synchronous_commit ON (scripts/with_postgres.sh turns fsync off), 1 and 16 clients.
# PostgreSQL serializes the commits of NOTIFY-sending transactions cluster-wide (a lock taken in
# PreCommit_Notify and held until the commit ends), which this shows. Run by hand, as root or a
# user PostgreSQL runs as:   bash bench/pg_notify_commit_cost.sh    (SECS=8 per run by default)
set -euo pipefail
bin=${LOCUS_PG_BIN:-$( (ls -d /usr/lib/postgresql/*/bin 2>/dev/null || true) | sort -V | tail -n 1)}
dir=$(mktemp -d "${TMPDIR:-/tmp}/locus-pgnotify.XXXXXX")
as_pg() { if [ "$(id -u)" = 0 ]; then (cd "$dir" && runuser -u nobody -- "$@"); else "$@"; fi; }
trap 'as_pg "$bin/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true; rm -rf "$dir"' EXIT
if [ "$(id -u)" = 0 ]; then chown nobody "$dir"; fi
chmod 755 "$dir"
as_pg "$bin/initdb" -D "$dir/data" -A trust -U locus -E UTF8 >/dev/null
as_pg "$bin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -o "-k $dir -h '' -c fsync=on -c synchronous_commit=on" start >/dev/null
as_pg "$bin/psql" -h "$dir" -U locus -d postgres -q <<'SQL'
CREATE TABLE tracks (id bigint PRIMARY KEY, last_fix_at double precision);
CREATE TABLE track_fixes (track_id bigint, t double precision, floor_id bigint, x double precision, y double precision,
                          accuracy_m double precision, PRIMARY KEY (track_id, t));
INSERT INTO tracks SELECT g, 0 FROM generate_series(1, 64) g;
SQL
post='\set tr :client_id + 1
BEGIN;
INSERT INTO track_fixes VALUES (:tr, extract(epoch from clock_timestamp()) + random(), 1, 1, 1, 1.5) ON CONFLICT DO NOTHING;
UPDATE tracks SET last_fix_at = extract(epoch from clock_timestamp()) WHERE id = :tr;'
notify="SELECT pg_notify('locus_tracks', '{\"origin\":\"bench\",\"changes\":[{\"kind\":\"tracks\",\"id\":' || :tr || ',\"map_id\":1}]}');"
printf '%s\nCOMMIT;\n' "$post" >"$dir/plain.sql"
printf '%s\n%s\nCOMMIT;\n' "$post" "$notify" >"$dir/notify.sql"
chmod a+r "$dir"/*.sql
for c in 1 16; do
  for s in plain notify plain notify; do
    echo "clients=$c $s: $(as_pg "$bin/pgbench" -h "$dir" -U locus -n -c $c -j 2 -T "${SECS:-8}" -f "$dir/$s.sql" postgres 2>&1 |
      grep -E '^(tps|latency average)' | tr '\n' ' ')"
  done
done
