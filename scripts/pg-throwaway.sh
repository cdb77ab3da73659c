#!/usr/bin/env bash
# A throwaway PostgreSQL cluster for the store's tests: `start DIR` makes a cluster in DIR (owned by the postgres user:
# initdb refuses root), listening on a unix socket in DIR and on 127.0.0.1:PORT (default 55432), creates the database
# pmacstream owned by an admin role, and a station role `station` with only what a station needs (connect, use the
# schema, read and write the store's tables; no CREATE ROLE, no superuser). It prints the connection string of the
# station role (PMACSTREAM_TEST_PG) and of the owner (PMACSTREAM_TEST_PG_ADMIN, which runs the migrations) as
# `export` lines, and the cluster's data folder (PMACSTREAM_TEST_PG_DIR: the restart test stops and starts the server
# with `pg_ctl -D` as the postgres user). Over TCP every role needs its password (scram-sha-256). `stop DIR` stops it
# and removes DIR. PORT=N picks another port (engineers sharing a machine each take their own).
set -euo pipefail
cmd=${1:?start|stop DIR}; dir=${2:?DIR}; port=${PORT:-55432}
bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
[ -x "$bin/initdb" ] || { echo "pg-throwaway: PostgreSQL is not installed (apt-get install postgresql)" >&2; exit 2; }
as_pg() { if [ "$(id -u)" = 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi; }
case $cmd in
start)
  mkdir -p "$dir"; [ "$(id -u)" = 0 ] && chown postgres:postgres "$dir"
  as_pg "$bin/initdb" -D "$dir/data" -U postgres --auth-local=trust --auth-host=scram-sha-256 -E UTF8 >/dev/null
  # The server's address in its own configuration, so a plain `pg_ctl -D DIR/data start` (the restart test's) serves
  # the same port and socket again.
  printf "listen_addresses = '127.0.0.1'\nport = %s\nunix_socket_directories = '%s'\nfsync = off\nfull_page_writes = off\n" "$port" "$dir" \
    | as_pg tee -a "$dir/data/postgresql.conf" >/dev/null
  as_pg "$bin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w start >/dev/null
  psql_() { as_pg psql -h "$dir" -p "$port" -U postgres -v ON_ERROR_STOP=1 -q "$@"; }  # the unix socket: trusted, for the set-up only
  psql_ -d postgres -c "CREATE ROLE pmacstream_owner LOGIN PASSWORD 'owner-secret'" \
        -c "CREATE DATABASE pmacstream OWNER pmacstream_owner" \
        -c "CREATE ROLE station LOGIN PASSWORD 'station-secret'"
  # The owner creates the schema (migrations); a station may only read and write its rows.
  psql_ -d pmacstream -c "REVOKE CREATE ON SCHEMA public FROM PUBLIC" -c "GRANT USAGE ON SCHEMA public TO station" \
        -c "ALTER DEFAULT PRIVILEGES FOR ROLE pmacstream_owner IN SCHEMA public GRANT SELECT, INSERT, UPDATE, DELETE ON TABLES TO station" \
        -c "ALTER DEFAULT PRIVILEGES FOR ROLE pmacstream_owner IN SCHEMA public GRANT USAGE, SELECT ON SEQUENCES TO station"
  echo "export PMACSTREAM_TEST_PG='Host=127.0.0.1;Port=$port;Database=pmacstream;Username=station;Password=station-secret'"
  echo "export PMACSTREAM_TEST_PG_ADMIN='Host=127.0.0.1;Port=$port;Database=pmacstream;Username=pmacstream_owner;Password=owner-secret'"
  echo "export PMACSTREAM_TEST_PG_DIR='$dir/data'"
  ;;
stop)
  [ -d "$dir/data" ] && as_pg "$bin/pg_ctl" -D "$dir/data" -m fast -w stop >/dev/null || true
  rm -rf "$dir"
  ;;
*) echo "usage: $0 start|stop DIR" >&2; exit 2;;
esac
