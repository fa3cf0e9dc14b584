#!/bin/bash
# The page's CPU in a browser: the main job with a view (EPISODES
# episodes), headless Chromium (Debian's `chromium`, or CHROMIUM; the page
# tests' flags, software rendering) showing the page (QUERY: its query,
# e.g. "?every=2"); after 6 s, WINDOWS times, each process's CPU over
# WINDOW_SECONDS s (user+system from /proc/PID/stat; counted in 10 ms ticks), in % of
# one core: the view process and every browser process by type, and the
# browser's total.
#   BIN=target/release bash scripts/measure-page-cpu.sh
#   QUERY="?every=2" WINDOWS=3 WINDOW_SECONDS=15 EPISODES=15000 BIN=target/release bash scripts/measure-page-cpu.sh
set -u
BIN=${BIN:-target/release}
EPISODES=${EPISODES:-5000}
PORT=${PORT:-18899}
CHROMIUM=${CHROMIUM:-chromium}
QUERY=${QUERY:-}
WINDOWS=${WINDOWS:-1}
SECONDS_EACH=${WINDOW_SECONDS:-8}
out=$(mktemp -d); profile=$(mktemp -d)
"$BIN/learnpnp-supervisor" --out "$out/run" --episodes "$EPISODES" --view=127.0.0.1:$PORT > "$out/run.log" 2>&1 &
run=$!
until ss -ltnH "sport = :$PORT" | grep -q .; do sleep 0.05; done
"$CHROMIUM" $(grep -v '^#' "$(dirname "$0")/chromium-flags") --user-data-dir="$profile" --remote-debugging-port=0 "http://127.0.0.1:$PORT/$QUERY" > "$out/browser.log" 2>&1 &
browser=$!
sleep 6
ticks() {
  for p in $(pgrep -f "user-data-dir=$profile") $(pgrep -f learnpnp-view); do
    kind=$(tr '\0' ' ' < /proc/$p/cmdline | grep -o -- '--type=[a-z-]*\|learnpnp-view' | head -1)
    echo "$p:${kind:-browser} $(awk '{print $14 + $15}' /proc/$p/stat)"
  done | sort
}
hz=$(getconf CLK_TCK)
for window in $(seq 1 "$WINDOWS"); do
  ticks > "$out/t0"; sleep "$SECONDS_EACH"; ticks > "$out/t1"
  echo "window $window ($SECONDS_EACH s):"
  join "$out/t0" "$out/t1" | awk -v hz="$hz" -v s="$SECONDS_EACH" '{c = ($3 - $2) * 100 / hz / s; if ($1 !~ /learnpnp-view/) t += c; printf "%-28s %5.2f%%\n", $1, c} END {printf "%-28s %5.2f%%\n", "browser total", t}'
done
kill $browser; wait $browser 2>/dev/null; wait $run
grep -o '[0-9,]* cycles/s' "$out/run.log"
rm -rf "$out" "$profile"
