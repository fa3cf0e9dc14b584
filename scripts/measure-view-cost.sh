#!/bin/bash
# The live view's cost on the main job: `learnpnp-supervisor` on its
# defaults without a view and with one, alternating, ROUNDS rounds. MODES
# picks the runs of a round (default "none page"):
#   none    no view;
#   served  `--view`, no client connected (the agents' feed and the view
#           process alone);
#   blank   no view; a browser open on a blank page through the run:
#           headless Chromium (Debian's `chromium`, or CHROMIUM; the page
#           tests' flags, software rendering), started and settled before
#           the run (a designer's browser, the page not open);
#   page    `--view` and the page open: the same browser, started and
#           settled on a blank page before the run, opens http://ADDR/ in a
#           tab once the view listens;
#   page2   the same, the page redrawn every 2 s (http://ADDR/?every=2);
#   client  `--view` and a Foxglove client (foxglove_client.py, stdlib only)
#           subscribed to the channels the page subscribes to live
#           (`LIVE_TOPICS` in crates/view/page/app.js);
#   all     `--view` and the same client subscribed to every channel (a
#           Foxglove app showing everything).
# The modes' order turns by one each round.
# Prints, per run: the load before it, the run's cycles/s, its wall time and
# the CPU its processes used (user+system, the supervisor and every child it
# waited for: simulator, keepers, view), the client's messages and CPU (the
# browser's CPU, all its processes, for blank and page); then
# each mode's median against BASE's (default: the first of MODES), and
# whether every run's
# episodes.csv is byte-identical. ARGS are passed to every run (none: the
# main job's defaults); CLIENT_PREFIX runs the client under a command (e.g.
# "chrt -b 0": as a background process).
# JOB=experiment measures the same in one process: `learnpnp experiment
# $EXPERIMENT` (default: keepaway-position, Soft-SoSMC, two runs on the
# machine's two cores), its cycles/s read from its summary.json.
#   BIN=target/release ROUNDS=5 bash scripts/measure-view-cost.sh
#   ARGS="--episodes 3000" MODES="none served page all" bash scripts/measure-view-cost.sh
#   MODES="blank page" bash scripts/measure-view-cost.sh   # the browser open in both
set -u
BIN=${BIN:-target/release}
OUT=${OUT:-/tmp/viewcost}
ROUNDS=${ROUNDS:-5}
ARGS=${ARGS:-}
MODES=${MODES:-none page}
CLIENT_PREFIX=${CLIENT_PREFIX:-}
BASE=${BASE:-${MODES%% *}}
CHROMIUM=${CHROMIUM:-chromium}
JOB=${JOB:-supervisor}
EXPERIMENT=${EXPERIMENT:-keepaway-position --algo soft-sosmc --runs 2}
HERE=$(dirname "$0")
PAGE_TOPICS=$(grep -E '^const (LIVE_TOPICS|BUNDLE) ' "$HERE/../../crates/view/page/app.js" | grep -o '"/learnpnp/[a-z]*"' | tr -d '"' | sort -u)
rm -rf "$OUT"; mkdir -p "$OUT"
echo "commit $(git -C "$HERE" rev-parse --short HEAD 2>/dev/null)$(git -C "$HERE" diff --quiet 2>/dev/null || echo +changes), binaries $BIN, $(nproc) cores, $(date -u +%FT%TZ), job: $JOB$([ $JOB = experiment ] && echo " $EXPERIMENT"), args: ${ARGS:-(defaults)}"
echo "the page's channels: $(echo $PAGE_TOPICS)"
printf '%-6s %-5s %-16s %10s %8s %8s %9s %10s\n' mode round load-before cycles/s wall_s cpu_s messages client_cpu_s
# The browser is started (on a blank page) and settled before the run, as a
# browser a designer already has open; page opens the page in it once the
# view listens. Its CPU (all its processes) is counted from the run's start.
start_browser() {
  profile=$(mktemp -d)
  "$CHROMIUM" $(grep -v '^#' "$HERE/chromium-flags") --user-data-dir="$profile" \
    --remote-debugging-port=$((19200 + round)) about:blank > "$dir.browser" 2>&1 &
  browser=$!
  sleep 3
  before=$(browser_ticks)
}
browser_ticks() { for p in $(pgrep -f "user-data-dir=$profile"); do awk '{print $14 + $15}' /proc/$p/stat; done | paste -sd+ | bc; }
read -ra modes <<< "$MODES"
for round in $(seq 1 "$ROUNDS"); do
  # Each round starts one mode later than the one before (none, served, page;
  # then served, page, none; ...): no mode always runs first or last.
  for i in $(seq 0 $((${#modes[@]} - 1))); do
    mode=${modes[$(((i + round - 1) % ${#modes[@]}))]}
    dir=$OUT/$mode-$round
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    case $JOB in
      supervisor) run=("$BIN/learnpnp-supervisor" --out "$dir" $ARGS) ;;
      experiment) run=("$BIN/learnpnp" experiment $EXPERIMENT --out "$dir" $ARGS) ;;
      *) echo "unknown job $JOB" >&2; exit 2 ;;
    esac
    client=
    case $mode in
      none) ;;
      served) run+=(--view=127.0.0.1:0) ;;
      blank)
        start_browser
        client= ;;
      page | page2)
        port=$((18800 + round))
        run+=(--view=127.0.0.1:$port)
        query=; [ $mode = page2 ] && query="%3Fevery=2"
        start_browser
        ( until ss -ltnH "sport = :$port" | grep -q .; do sleep 0.05; done
          curl -s -X PUT "http://127.0.0.1:$((19200 + round))/json/new?http://127.0.0.1:$port/$query" > /dev/null ) &
        client=$! ;;
      client | all)
        port=$((18800 + round))
        run+=(--view=127.0.0.1:$port)
        topics=; [ $mode = client ] && topics=$PAGE_TOPICS
        $CLIENT_PREFIX python3 "$HERE/foxglove_client.py" 127.0.0.1 $port $topics > "$dir.client" 2>&1 &
        client=$! ;;
      *) echo "unknown mode $mode" >&2; exit 2 ;;
    esac
    /usr/bin/time -f '%e %U %S' -o "$dir.time" "${run[@]}" > "$dir.log" 2>&1
    [ -n "$client" ] && wait $client
    if [ $mode = page ] || [ $mode = page2 ] || [ $mode = blank ]; then
      echo "messages - client_cpu_s $(echo "scale=2; ($(browser_ticks) - $before) / $(getconf CLK_TCK)" | bc)" > "$dir.client"
      kill $browser; wait $browser 2>/dev/null; rm -rf "$profile"
    fi
    if [ $JOB = supervisor ]; then
      cycles=$(grep -o '[0-9,.]* cycles/s' "$dir.log" | head -1 | cut -d' ' -f1 | tr -d ,)
    else
      cycles=$(python3 -c 'import json, sys; print(round(json.load(open(sys.argv[1]))["cycles_per_second"]))' "$dir/summary.json")
    fi
    read -r wall user sys < <(tail -1 "$dir.time")
    cpu=$(echo "$user + $sys" | bc)
    messages=-; client_cpu=-
    if [ -f "$dir.client" ]; then
      messages=$(grep -o 'messages [0-9-]*' "$dir.client" | cut -d' ' -f2)
      client_cpu=$(grep -o 'client_cpu_s [0-9.]*' "$dir.client" | cut -d' ' -f2)
    fi
    printf '%-6s %-5s %-16s %10s %8s %8s %9s %10s\n' $mode "$round" "$load" "${cycles:-?}" "$wall" "$cpu" "${messages:-?}" "${client_cpu:-?}"
    echo "$mode $cycles" >> "$OUT/cycles"
  done
done
median() { grep "^$1 " "$OUT/cycles" | cut -d' ' -f2 | sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
base=$(median "$BASE")
for mode in $MODES; do
  [ "$mode" = "$BASE" ] && continue
  m=$(median $mode)
  echo "median cycles/s: $BASE $base, $mode $m; ratio $(echo "scale=4; $m / $base" | bc) (bound: >= 0.97)"
done
if [ "$(md5sum "$OUT"/*/episodes.csv | cut -d' ' -f1 | sort -u | wc -l)" = 1 ]; then
  echo "episodes.csv: byte-identical in all $(ls "$OUT"/*/episodes.csv | wc -l) runs"
else
  echo "episodes.csv: DIFFERS between runs"; md5sum "$OUT"/*/episodes.csv
fi
