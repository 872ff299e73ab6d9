#!/usr/bin/env bash
# with_postgres.sh CMD…: runs CMD with a throwaway PostgreSQL cluster, then stops and deletes it
# whatever CMD did. The cluster lives in a temp dir (initdb, trust authentication), listens on
# a unix socket there and on 127.0.0.1 at a free port; CMD sees it as
#   LOCUS_TEST_DB_URL=postgresql://locus@127.0.0.1:PORT/postgres
# (the integration tests create an empty database of their own on it for each server).
# PostgreSQL refuses to run as root: as root, the cluster runs as user nobody.
set -euo pipefail
if [ $# -eq 0 ]; then
  echo "usage: scripts/with_postgres.sh CMD [ARG…]" >&2
  exit 2
fi
bin=${LOCUS_PG_BIN:-$( (ls -d /usr/lib/postgresql/*/bin 2>/dev/null || true) | sort -V | tail -n 1)}
if [ -z "$bin" ] || [ ! -x "$bin/initdb" ]; then
  echo "with_postgres.sh: no PostgreSQL server binaries (Debian package postgresql)" >&2
  exit 1
fi
dir=$(mktemp -d "${TMPDIR:-/tmp}/locus-pg.XXXXXX")
as_pg() {
  # From the cluster's own dir: user nobody may not be allowed into the caller's.
  if [ "$(id -u)" = 0 ]; then (cd "$dir" && runuser -u nobody -- "$@"); else "$@"; fi
}
cleanup() {
  as_pg "$bin/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true
  rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
if [ "$(id -u)" = 0 ]; then chown nobody "$dir"; fi
chmod 700 "$dir"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
as_pg "$bin/initdb" -D "$dir/data" -A trust -U locus --no-sync -E UTF8 >"$dir/initdb.log" 2>&1 ||
  { cat "$dir/initdb.log" >&2; exit 1; }
# Tuned for throwaway data: the cluster is deleted afterwards, and the tests need its semantics,
# not its durability (a test kills locus-server, never PostgreSQL). fsync off (-F), commits not
# waiting for their WAL flush, no full-page images after a checkpoint.
as_pg "$bin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 60 \
  -o "-k $dir -h 127.0.0.1 -p $port -F -c max_connections=300 -c synchronous_commit=off -c full_page_writes=off" \
  start >/dev/null ||
  { cat "$dir/server.log" >&2; exit 1; }
export LOCUS_TEST_DB_URL="postgresql://locus@127.0.0.1:$port/postgres"
set +e
"$@"
rc=$?
set -e
exit $rc
