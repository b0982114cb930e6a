#!/usr/bin/env bash
# A throw-away PostgreSQL cluster, for the tests and for trying `lambert serve --store` by hand:
#   tools/pg-throwaway.sh start DIR   creates a cluster in DIR (new or empty), starts it listening only
#                                     on a Unix socket in DIR, and prints its connection URI
#   tools/pg-throwaway.sh stop DIR    stops it and removes DIR
# Debian's `postgresql` package provides the server (tools/install-deps.sh installs it). initdb
# refuses to run as root, so under root the cluster belongs to the `postgres` user that the package
# creates, and its commands run through runuser. fsync is off: the cluster is thrown away.
set -euo pipefail
if [ $# -ne 2 ] || { [ "$1" != start ] && [ "$1" != stop ]; }; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi
command=$1
self=$(realpath "$0")
dir=$(realpath -m "$2")
cd /  # the cluster's owner may not be allowed into the caller's directory
bindir=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
if [ -z "$bindir" ]; then
  echo "$0: no PostgreSQL server under /usr/lib/postgresql (apt-get install postgresql)" >&2
  exit 1
fi
as_owner() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}
case $command in
  start)
    if [ -d "$dir/data" ]; then "$self" stop "$dir"; fi  # left by an interrupted run
    mkdir -p "$dir"
    chmod 700 "$dir"
    if [ "$(id -u)" -eq 0 ]; then chown postgres: "$dir"; fi
    as_owner "$bindir/initdb" -D "$dir/data" -A trust -U lambert -E UTF8 --locale=C --no-sync > "$dir/initdb.log" 2>&1 ||
      { cat "$dir/initdb.log" >&2; exit 1; }
    as_owner "$bindir/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 60 \
      -o "-k $dir -c listen_addresses= -c fsync=off -c max_connections=200 -p 5432" start \
      < /dev/null > /dev/null 2>&1 || { cat "$dir/server.log" >&2; exit 1; }
    echo "postgresql://lambert@/postgres?host=$dir&port=5432"
    ;;
  stop)
    if [ -d "$dir/data" ]; then
      as_owner "$bindir/pg_ctl" -D "$dir/data" -m immediate -w stop < /dev/null > /dev/null 2>&1 || true
    fi
    rm -rf "$dir"
    ;;
esac
