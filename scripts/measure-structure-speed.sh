#!/bin/bash
# Two checkouts against each other: the criterion benches and the main job's cycles/s of
# two checkouts (BASE, HEAD), alternating. Each checkout must have been built
# first, in its own directory:
#   cargo bench --no-run -p learnpnp -p learnpnp-system \
#     --bench executor_step --bench keepaway_sim --bench keepaway_plans --bench parr_russell
#   cargo build --release --bins
# Usage: BASE=../old HEAD=. ROUNDS=3 SUPERVISOR_ROUNDS=3 OUT=/tmp/structure-speed \
#          bash scripts/measure-structure-speed.sh
# Each bench binary runs once a round on each side, the two sides next to each
# other (base first in odd rounds, head first in even ones); then the
# supervisor on its defaults, the same way. Writes $OUT/benches.tsv,
# $OUT/supervisor.tsv and the summary table ($OUT/summary.md); every run's
# output is kept under $OUT/raw.
set -euo pipefail
BASE=$(cd "${BASE:?the base checkout}" && pwd)
HEAD=$(cd "${HEAD:?the head checkout}" && pwd)
ROUNDS=${ROUNDS:-3}
SUPERVISOR_ROUNDS=${SUPERVISOR_ROUNDS:-3}
OUT=${OUT:-/tmp/structure-speed}
CRITERION_ARGS=${CRITERION_ARGS:---warm-up-time 1 --measurement-time 3 --sample-size 10 --noplot}
# The system crate's ipc_roundtrip and wake_latency can be added (BENCHES=...).
BENCHES=${BENCHES:-executor_step keepaway_sim keepaway_plans parr_russell}
NICE=${NICE:-nice -n 19}
mkdir -p "$OUT/raw"
# Our own iceoryx2 root: nothing here touches another run's files.
export LEARNPNP_IPC_DIR=${LEARNPNP_IPC_DIR:-$OUT/ipc}
mkdir -p "$LEARNPNP_IPC_DIR"

# The newest bench executable of that name in a checkout.
bench_bin() {
  find "$1/target/release/deps" -maxdepth 1 -type f -executable -name "$2-*" -printf '%T@ %p\n' |
    sort -n | tail -1 | cut -d' ' -f2
}

# The sides in a round's order.
order() { if [ $(($1 % 2)) = 1 ]; then echo "base head"; else echo "head base"; fi; }
dir_of() { if [ "$1" = base ]; then echo "$BASE"; else echo "$HEAD"; fi; }

for round in $(seq 1 "$ROUNDS"); do
  for bench in $BENCHES; do
    for side in $(order "$round"); do
      dir=$(dir_of "$side")
      bin=$(bench_bin "$dir" "$bench")
      [ -n "$bin" ] || { echo "no $bench binary in $dir" >&2; exit 1; }
      log=$OUT/raw/bench-$round-$side-$bench.txt
      echo "# $(date -u +%FT%TZ) $(uptime)" > "$log"
      # From the checkout: criterion keeps its files under its target/criterion.
      rm -rf "$dir/target/criterion"
      # shellcheck disable=SC2086
      (cd "$dir" && $NICE "$bin" --bench $CRITERION_ARGS) >> "$log" 2>&1
      # Criterion prints the mean; its median is in estimates.json.
      (cd "$dir/target/criterion" 2>/dev/null && find . -path '*/new/estimates.json' | while read -r e; do
        echo "median $(dirname "$(dirname "${e#./}")") $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["median"]["point_estimate"])' "$e")"
      done) >> "$log"
      echo "round $round $side $bench: $(grep -c 'time:' "$log") ids; $(uptime | sed 's/.*load/load/')"
    done
  done
done

for round in $(seq 1 "$SUPERVISOR_ROUNDS"); do
  for side in $(order "$round"); do
    dir=$(dir_of "$side")
    run=$OUT/raw/supervisor-$round-$side
    rm -rf "$run"
    echo "# $(date -u +%FT%TZ) $(uptime)" > "$run.log"
    (cd "$dir" && $NICE target/release/learnpnp-supervisor --out "$run") >> "$run.log" 2>&1
    echo "supervisor round $round $side: $(grep -o '[0-9,.]* cycles/s' "$run.log" | head -1); $(uptime | sed 's/.*load/load/')"
  done
done

python3 - "$OUT" "$ROUNDS" "$SUPERVISOR_ROUNDS" <<'EOF'
import glob, json, os, re, statistics, sys
out, rounds, sup_rounds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
unit = {"ps": 1e-3, "ns": 1.0, "µs": 1e3, "us": 1e3, "ms": 1e6, "s": 1e9}
rows = []  # (round, side, id, mean ns): what criterion prints
medians = []  # (round, side, id, median ns): criterion's estimates.json
for path in sorted(glob.glob(f"{out}/raw/bench-*.txt")):
    _, r, side, bench = os.path.basename(path)[:-4].split("-", 3)
    last = None
    for line in open(path, encoding="utf-8", errors="replace"):
        m = re.match(r"^(\S.*?)\s+time:\s+\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", line)
        if m:
            rows.append((int(r), side, m.group(1), float(m.group(2)) * unit[m.group(3)]))
            continue
        m = re.match(r"^\s+time:\s+\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", line)
        if m and last:
            rows.append((int(r), side, last, float(m.group(1)) * unit[m.group(2)]))
            continue
        m = re.match(r"^median (\S+) (\S+)$", line)
        if m:
            medians.append((int(r), side, m.group(1), float(m.group(2))))
            continue
        m = re.match(r"^\s*(listener|waitset): median (\S+) us", line)
        if m:
            rows.append((int(r), side, f"wake_latency/{m.group(1)}", float(m.group(2)) * 1e3))
            continue
        if line.strip() and not line[0].isspace() and not line.startswith(("#", "Benchmarking", "Found", "Warning", "change", "Gnuplot", "wake-up")):
            last = line.strip()
with open(f"{out}/benches.tsv", "w") as f:
    f.write("round\tside\tid\tmean_ns\tmedian_ns\n")
    for r, s, i, v in rows:
        f.write("%d\t%s\t%s\t%.3f\t\n" % (r, s, i, v))
    for r, s, i, v in medians:
        f.write("%d\t%s\t%s\t\t%.3f\n" % (r, s, i, v))
# The summary reads the medians where criterion wrote them, the printed means
# otherwise. Criterion's folder is the group, then the function's name with
# each '/' written '_': the median is named back as criterion prints it.
def folder(i):
    group, _, name = i.partition("/")
    return f"{group}/{name.replace('/', '_')}" if name else i
printed = {folder(i): i for _, _, i, _ in rows}
medians = [(r, s, printed.get(i, i), v) for r, s, i, v in medians]
ids_with_median = {i for _, _, i, _ in medians}
rows = [row for row in rows if row[2] not in ids_with_median] + medians
sup = []  # (round, side, cycles/s, episodes.csv)
for r in range(1, sup_rounds + 1):
    for side in ("base", "head"):
        s = f"{out}/raw/supervisor-{r}-{side}/summary.json"
        if os.path.exists(s):
            summary = json.load(open(s))
            cps = next(v for k, v in summary.items() if "cycles_per_s" in k)
            sup.append((r, side, float(cps), f"{out}/raw/supervisor-{r}-{side}/episodes.csv"))
with open(f"{out}/supervisor.tsv", "w") as f:
    f.write("round\tside\tcycles_per_second\n")
    for r, side, cps, _ in sup:
        f.write(f"{r}\t{side}\t{cps:.1f}\n")

def fmt(ns):
    for u, k in (("s", 1e9), ("ms", 1e6), ("us", 1e3)):
        if ns >= k:
            return f"{ns / k:.3g} {u}"
    return f"{ns:.3g} ns"

ids = list(dict.fromkeys(i for _, _, i, _ in rows))
with open(f"{out}/summary.md", "w") as f:
    f.write("| bench id | base | head | head/base | spread base, head (max/min) | base rounds | head rounds |\n|---|---|---|---|---|---|---|\n")
    for i in ids:
        b = [v for r, s, j, v in sorted(rows) if j == i and s == "base"]
        h = [v for r, s, j, v in sorted(rows) if j == i and s == "head"]
        if not b or not h:
            continue
        mb, mh = statistics.median(b), statistics.median(h)
        spread = f"{max(b) / min(b):.2f}, {max(h) / min(h):.2f}"
        f.write(f"| {i} | {fmt(mb)} | {fmt(mh)} | {mh / mb:.3f} | {spread} | {', '.join(fmt(v) for v in b)} | {', '.join(fmt(v) for v in h)} |\n")
    if sup:
        b = [c for _, s, c, _ in sup if s == "base"]
        h = [c for _, s, c, _ in sup if s == "head"]
        f.write(f"\nmain job (cycles/s, higher is faster): base {', '.join(f'{v:,.0f}' for v in b)} (median {statistics.median(b):,.0f}); "
                f"head {', '.join(f'{v:,.0f}' for v in h)} (median {statistics.median(h):,.0f}); head/base {statistics.median(h) / statistics.median(b):.3f}\n")
        csvs = [open(p, "rb").read() for _, _, _, p in sup if os.path.exists(p)]
        f.write(f"episodes.csv: {len(set(csvs))} distinct content(s) over {len(csvs)} runs\n")
print(open(f"{out}/summary.md").read())
EOF
