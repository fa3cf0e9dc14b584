#!/bin/bash
# What a redraw costs a software-rendering browser, whatever draws it (issue
# 40): the pages of page-raster/ (one scene, about what the view's page draws,
# new each second, drawn in SVG and HTML, on a canvas, on an OffscreenCanvas
# in a worker; and, to compare, a tiny change, an empty frame, no frame),
# served on loopback, each opened in a headless browser alone on an otherwise
# idle machine: Chromium (the flags in chromium-flags), or with
# BROWSER=firefox Firefox ESR (`firefox-esr`, a 1400x900 window); after
# SETTLE s, WINDOWS windows of WINDOW_SECONDS s, the CPU of all the browser's
# processes (user + system from /proc/PID/stat, 10 ms ticks) in % of one
# core, ROUNDS times.
#   bash docs/results/measure-page-raster.sh
#   ROUNDS=3 PAGES="svg offscreen" BROWSER=firefox bash docs/results/measure-page-raster.sh
set -u
here=$(cd "$(dirname "$0")" && pwd)
BROWSER=${BROWSER:-chromium}
CHROMIUM=${CHROMIUM:-chromium}
SETTLE=${SETTLE:-6}
PORT=${PORT:-18877}
ROUNDS=${ROUNDS:-2}
WINDOWS=${WINDOWS:-3}
SECONDS_EACH=${WINDOW_SECONDS:-15}
PAGES=${PAGES:-static empty tiny svg canvas offscreen}
python3 -m http.server "$PORT" --bind 127.0.0.1 --directory "$here/page-raster" > /dev/null 2>&1 &
server=$!
trap 'kill $server 2>/dev/null' EXIT
until python3 -c "import socket; socket.create_connection(('127.0.0.1', $PORT), 0.2)" 2> /dev/null; do sleep 0.05; done
# A process and all its descendants.
tree() {
  echo "$1"
  for child in $(pgrep -P "$1"); do tree "$child"; done
}
ticks() {
  for p in $(tree "$1"); do
    echo "$p $(awk '{print $14 + $15}' "/proc/$p/stat" 2> /dev/null || echo 0)"
  done | sort
}
hz=$(getconf CLK_TCK)
for round in $(seq 1 "$ROUNDS"); do
  for page in $PAGES; do
    profile=$(mktemp -d)
    url="http://127.0.0.1:$PORT/$page.html"
    if [ "$BROWSER" = firefox ]; then
      firefox-esr --headless --no-remote --profile "$profile" --window-size=1400,900 "$url" > /dev/null 2>&1 &
    else
      "$CHROMIUM" $(grep -v '^#' "$here/chromium-flags") --user-data-dir="$profile" "$url" > /dev/null 2>&1 &
    fi
    browser=$!
    sleep "$SETTLE"
    line="round $round $BROWSER $page:"
    for window in $(seq 1 "$WINDOWS"); do
      ticks "$browser" > "$profile.t0"; sleep "$SECONDS_EACH"; ticks "$browser" > "$profile.t1"
      line="$line $(join "$profile.t0" "$profile.t1" | awk -v hz="$hz" -v s="$SECONDS_EACH" '{t += $3 - $2} END {printf "%.2f%%", t * 100 / hz / s}')"
    done
    echo "$line"
    kill $(tree "$browser") 2> /dev/null; wait $browser 2> /dev/null
    rm -rf "$profile" "$profile.t0" "$profile.t1"
  done
done
