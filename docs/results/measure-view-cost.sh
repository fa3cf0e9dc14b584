#!/bin/bash
# The live view's cost on the main job (issue 40): `learnpnp-supervisor` on its
# defaults without a view, then with `--view` and a Foxglove client
# (foxglove_client.py, stdlib only) subscribed to every channel, alternating,
# ROUNDS rounds. Prints, per run: the load before it (uptime), the run's
# cycles/s, its wall time and the CPU its processes used (user+system, the
# supervisor and every child it waited for: simulator, keepers, view), the
# client's messages and CPU; then the medians, the ratio of the medians and
# whether every run's episodes.csv is byte-identical.
# ARGS are passed to every run (none: the main job's defaults).
#   BIN=target/release ROUNDS=3 bash docs/results/measure-view-cost.sh
#   ARGS="--episodes 2000" bash docs/results/measure-view-cost.sh   # shorter, on a busy machine
set -u
BIN=${BIN:-target/release}
OUT=${OUT:-/tmp/viewcost}
ROUNDS=${ROUNDS:-3}
ARGS=${ARGS:-}
HERE=$(dirname "$0")
rm -rf "$OUT"; mkdir -p "$OUT"
echo "commit $(git -C "$HERE" rev-parse --short HEAD 2>/dev/null)$(git -C "$HERE" diff --quiet 2>/dev/null || echo +changes), binaries $BIN, $(nproc) cores, $(date -u +%FT%TZ), args: ${ARGS:-(defaults)}"
printf '%-5s %-5s %-18s %10s %8s %8s %9s %10s\n' mode round load-before cycles/s wall_s cpu_s messages client_cpu_s
for round in $(seq 1 "$ROUNDS"); do
  for mode in none view; do
    dir=$OUT/$mode-$round
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    if [ $mode = view ]; then
      port=$((18800 + round))
      python3 "$HERE/foxglove_client.py" 127.0.0.1 $port > "$dir.client" 2>&1 &
      client=$!
      /usr/bin/time -f '%e %U %S' -o "$dir.time" "$BIN/learnpnp-supervisor" --out "$dir" $ARGS --view=127.0.0.1:$port > "$dir.log" 2>&1
      wait $client
    else
      /usr/bin/time -f '%e %U %S' -o "$dir.time" "$BIN/learnpnp-supervisor" --out "$dir" $ARGS > "$dir.log" 2>&1
    fi
    cycles=$(grep -o '[0-9,.]* cycles/s' "$dir.log" | head -1 | cut -d' ' -f1 | tr -d ,)
    read -r wall user sys < <(tail -1 "$dir.time")
    cpu=$(echo "$user + $sys" | bc)
    messages=-; client_cpu=-
    if [ -f "$dir.client" ]; then
      messages=$(grep -o 'messages [0-9]*' "$dir.client" | cut -d' ' -f2)
      client_cpu=$(grep -o 'client_cpu_s [0-9.]*' "$dir.client" | cut -d' ' -f2)
    fi
    printf '%-5s %-5s %-18s %10s %8s %8s %9s %10s\n' $mode "$round" "$load" "${cycles:-?}" "$wall" "$cpu" "${messages:-?}" "${client_cpu:-?}"
    echo "$mode $cycles" >> "$OUT/cycles"
  done
done
median() { grep "^$1 " "$OUT/cycles" | cut -d' ' -f2 | sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
none=$(median none); view=$(median view)
echo "median cycles/s: no view $none, view and client $view; ratio $(echo "scale=4; $view / $none" | bc) (bound: >= 0.97)"
if [ "$(md5sum "$OUT"/*/episodes.csv | cut -d' ' -f1 | sort -u | wc -l)" = 1 ]; then
  echo "episodes.csv: byte-identical in all $((2 * ROUNDS)) runs"
else
  echo "episodes.csv: DIFFERS between runs"; md5sum "$OUT"/*/episodes.csv
fi
