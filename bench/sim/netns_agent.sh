#!/bin/sh
# bench/sim/netns_agent.sh — Open MPI's "remote shell" for the two-namespace
# recipe (docs/parallel.md, "Across hosts"): `netns_agent.sh HOST CMD...` runs CMD in
# the network namespace that owns HOST's address.  Only the two fixed
# addresses of the recipe are known; anything else is refused.
host=$1
shift
case "$host" in
10.77.0.1) ns=csgA ;;
10.77.0.2) ns=csgB ;;
*) echo "netns_agent.sh: unknown host $host" >&2; exit 2 ;;
esac
exec ip netns exec "$ns" sh -c "$*"
