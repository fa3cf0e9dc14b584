#!/bin/bash
# The main job with and without the live view (and a client on it), alternating.
BIN=${BIN:-target/release}
OUT=${OUT:-/tmp/viewcost}
rm -rf $OUT; mkdir -p $OUT
for round in 1 2 3; do
  for mode in none view; do
    dir=$OUT/$mode-$round
    if [ $mode = view ]; then
      port=$((18800 + round))
      (python3 "$(dirname "$0")/foxglove_client.py" 127.0.0.1 $port > $dir.client 2>&1 &)
      $BIN/learnpnp-supervisor --out $dir --view=127.0.0.1:$port > $dir.log 2>&1
    else
      $BIN/learnpnp-supervisor --out $dir > $dir.log 2>&1
    fi
    echo "$mode $round: $(grep -o '[0-9,.]* cycles/s' $dir.log | head -1) $(tail -c 300 $dir.client 2>/dev/null | tr '\n' ' ' | cut -c1-120)"
  done
done
