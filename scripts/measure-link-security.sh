#!/usr/bin/env bash
# The cost of the secure link (RESULTS.md "The secure link's cost"): the
# two-host lock-step run of measure-two-hosts.sh (keeper 3 on host B, the hosts
# two network namespaces joined by a veth pair 198.18.7.1 <-> 198.18.7.2) over
# the default link (QUIC, TLS 1.3 with mutual authentication by a private CA,
# access control on host A) against the same run over plain TCP
# (--insecure-plain-tcp), alternating, ROUNDS rounds (default 3) of one run
# each. Every run is --episodes 1000 --seed 2011 (keepaway-position defaults
# otherwise), so all of them play the same episodes: their episodes.csv must be
# byte-identical. Run as root from the repository root after
# cargo build --release --bins (BIN: where the binaries are, default
# target/release):
#   sudo bash scripts/measure-link-security.sh [RESULTS_DIR]
set -u
BIN=${BIN:-target/release}
S=$BIN/learnpnp-supervisor
ROUNDS=${ROUNDS:-3}
# No run may hang the script: each host's supervisor is stopped after this.
LIMIT=${LIMIT:-1800}
[ -x "$S" ] || { echo "no $S (cargo build --release --bins, or BIN=DIR)"; exit 1; }
command -v jq > /dev/null || { echo "needs jq"; exit 1; }
PIDS=()
# The runs still going (if the script is stopped) and the namespaces (with
# the veth pair in them) go even if the script is stopped.
cleanup() {
  for p in "${PIDS[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${PIDS[@]}"; do wait "$p" 2>/dev/null; done
  ip netns del lpma 2>/dev/null; ip netns del lpmb 2>/dev/null
}
trap cleanup EXIT
trap 'exit 130' INT TERM
ip netns add lpma || exit 1; ip netns add lpmb || exit 1
ip link add lvma type veth peer name lvmb
ip link set lvma netns lpma; ip link set lvmb netns lpmb
ip -n lpma addr add 198.18.7.1/30 dev lvma; ip -n lpmb addr add 198.18.7.2/30 dev lvmb
ip -n lpma link set lvma up; ip -n lpmb link set lvmb up; ip -n lpma link set lo up; ip -n lpmb link set lo up
R=${1:-/tmp/link-cost}; rm -rf "$R"; mkdir -p "$R"
# The run's CA and each host's certificates (host A's names 198.18.7.1).
$S link-certs --dir "$R/certs" --host-a 198.18.7.1 > "$R/link-certs.log" || { cat "$R/link-certs.log"; exit 1; }
LOCK="--episodes 1000 --seed 2011"
printf 'round\tmode\tcycles_per_second\tk3_p50\tk3_p99\tk3_p999\tsecurity\tidentical\n' > "$R/rounds.tsv"
FIRST=""
FAILED=0
# run ROUND MODE PORT: one two-host lock-step run, keeper 3 on host B.
run() {
  local round=$1 mode=$2 port=$3 name="$2-$1" a b ep
  if [ "$mode" = secure ]; then
    ep=quic/198.18.7.1:$port; a="--link-certs $R/certs/host-a"; b="--link-certs $R/certs/host-b"
  else
    ep=tcp/198.18.7.1:$port; a=--insecure-plain-tcp; b=--insecure-plain-tcp
  fi
  echo "== round $round, $mode ($ep)"
  LEARNPNP_IPC_DIR=$R/ipc-a-$name ip netns exec lpma timeout $LIMIT $S $LOCK --remote-agents 3 \
    --bridge-listen $ep $a --out "$R/$name" > "$R/$name.log" 2>&1 &
  local apid=$!
  sleep 0.5
  LEARNPNP_IPC_DIR=$R/ipc-b-$name ip netns exec lpmb timeout $LIMIT $S remote \
    --bridge-connect $ep $b --out "$R/$name-b" > "$R/$name-b.log" 2>&1 &
  local bpid=$!
  PIDS=("$apid" "$bpid")
  wait $apid; local arc=$?
  wait $bpid; local brc=$?
  PIDS=()
  local j=$R/$name/summary.json
  if [ $arc -ne 0 ] || [ $brc -ne 0 ] || [ ! -f "$j" ]; then
    echo "   FAILED: host A exit $arc, host B exit $brc (logs: $R/$name.log, $R/$name-b.log, $R/$name/runs/run-0/)"
    tail -n 5 "$R/$name.log" | sed 's/^/   A| /'; tail -n 5 "$R/$name-b.log" | sed 's/^/   B| /'
    FAILED=1
    [ -f "$j" ] || return
  fi
  local cps p50 p99 p999 sec same
  cps=$(jq -r '.cycles_per_second' "$j")
  p50=$(jq -r '.keeper_latency_us["keeper 3"].p50' "$j")
  p99=$(jq -r '.keeper_latency_us["keeper 3"].p99' "$j")
  p999=$(jq -r '.keeper_latency_us["keeper 3"].p999 // "-"' "$j")
  sec=$(jq -r '.link.security // "none"' "$j")
  if [ -z "$FIRST" ]; then
    FIRST=$R/$name/episodes.csv; same="(reference)"
  elif cmp -s "$FIRST" "$R/$name/episodes.csv"; then
    same=yes
  else
    same=NO; FAILED=1
  fi
  printf '   %.0f cycles/s; keeper 3 round trip p50 %.1f us, p99 %.1f, p99.9 %s; link %s; episodes.csv identical to %s: %s\n' \
    "$cps" "$p50" "$p99" "$p999" "$sec" "${FIRST#$R/}" "$same"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$round" "$mode" "$cps" "$p50" "$p99" "$p999" "$sec" "$same" >> "$R/rounds.tsv"
}
port=7447
for round in $(seq 1 "$ROUNDS"); do
  for mode in secure plain; do
    run "$round" "$mode" $port
    port=$((port + 1))
  done
done
median() { sort -g | awk '{v[NR]=$1} END {if (NR == 0) print "nan"; else if (NR % 2) print v[(NR+1)/2]; else print (v[NR/2]+v[NR/2+1])/2}'; }
col() { awk -F'\t' -v m="$1" -v c="$2" 'NR > 1 && $2 == m {print $c}' "$R/rounds.tsv"; }
echo "== every run ($R/rounds.tsv)"
column -t -s $'\t' "$R/rounds.tsv"
echo "== medians"
for mode in secure plain; do
  printf '%-7s %.0f cycles/s; keeper 3 p50 %.1f us, p99 %.1f us (%d runs)\n' "$mode" \
    "$(col $mode 3 | median)" "$(col $mode 4 | median)" "$(col $mode 5 | median)" "$(col $mode 3 | wc -l)"
done
awk -v cs="$(col secure 3 | median)" -v cp="$(col plain 3 | median)" \
    -v ls="$(col secure 4 | median)" -v lp="$(col plain 4 | median)" \
    'BEGIN {printf "secure/plain: cycles/s %.3f, keeper 3 p50 %.3f\n", cs / cp, ls / lp}'
if [ $FAILED -eq 0 ]; then
  echo "every run's episodes.csv identical: yes"
else
  echo "SOME RUN FAILED or played other episodes (see above)"
fi
exit $FAILED
