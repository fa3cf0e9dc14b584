#!/usr/bin/env bash
# The figures of RESULTS.md "More than one machine": Keepaway lock-step and
# real time on one host, then with keeper 3 on host B, the hosts two network
# namespaces joined by a veth pair (198.18.7.1 <-> 198.18.7.2), over the
# default link (QUIC, TLS 1.3 with mutual authentication by the private CA made
# into RESULTS_DIR/certs, access control on host A). Run as root from the
# repository root after cargo build --release --bins (BIN: where the binaries
# are, default target/release):
#   sudo bash scripts/measure-two-hosts.sh [RESULTS_DIR]
set -u
BIN=${BIN:-target/release}
S=$BIN/learnpnp-supervisor
SOAK=$BIN/learnpnp-soak
# The namespaces (and the veth pair in them) go even if the script is stopped.
trap 'ip netns del lpma 2>/dev/null; ip netns del lpmb 2>/dev/null' EXIT
ip netns add lpma; ip netns add lpmb
ip link add lvma type veth peer name lvmb
ip link set lvma netns lpma; ip link set lvmb netns lpmb
ip -n lpma addr add 198.18.7.1/30 dev lvma; ip -n lpmb addr add 198.18.7.2/30 dev lvmb
ip -n lpma link set lvma up; ip -n lpmb link set lvmb up; ip -n lpma link set lo up; ip -n lpmb link set lo up
R=${1:-/tmp/mh}; rm -rf $R; mkdir -p $R
# The run's CA and each host's certificates (host A's names 198.18.7.1).
$S link-certs --dir $R/certs --host-a 198.18.7.1 > $R/link-certs.log || { cat $R/link-certs.log; exit 1; }
CA="--link-certs $R/certs/host-a"; CB="--link-certs $R/certs/host-b"
# One experiment (NAME, its COMMAND: the supervisor's or the soak's, with its
# flags) on one host, then with keeper 3 on host B, its bridge on PORT; SHOW:
# the report's lines to print; LABEL: its heading.
one_then_two() {
  local name=$1 command=$2 port=$3 show=$4 label=$5
  echo "== $label, one host"; LEARNPNP_IPC_DIR=$R/i-$name $command --out $R/$name-one 2>&1 | grep -E "$show|^  keeper"
  echo "== $label, keeper 3 on host B"
  (LEARNPNP_IPC_DIR=$R/ia ip netns exec lpma $command --remote-agents 3 --bridge-listen quic/198.18.7.1:$port $CA --out $R/$name-two > $R/$name-two.log 2>&1 &)
  sleep 0.5; LEARNPNP_IPC_DIR=$R/ib ip netns exec lpmb $S remote --bridge-connect quic/198.18.7.1:$port $CB --out $R/$name-b > /dev/null 2>&1
  sleep 2; grep -E "$show|remote host|^  keeper" $R/$name-two.log
}
one_then_two lock "$S --episodes 2000 --seed 2011" 7447 "round trip|floor|cycles/s" "lock-step"
cmp $R/lock-one/episodes.csv $R/lock-two/episodes.csv && echo "episodes.csv identical"
one_then_two rt "$SOAK soak --duration 60 --mode realtime --seed 2011" 7448 "round trip|floor|cycles/s|missed" "real time"
