#!/usr/bin/env bash
# Regenerates docs/benchmarks.md and docs/images/bench/ from scratch:
#   1. Release build of `dynslam` and the micro-benchmarks (apps/bench/);
#   2. the rpy_walkers, rpy_close, rpy_panel and rpy_sitting composite sequences, built
#      once into the cache folder;
#   3. `dynslam bench --runs 5 --spread` on fr1_rpy (off, detect+flow),
#      rpy_walkers (all four modes), rpy_close, rpy_panel and rpy_sitting (off,
#      detect+flow) and the two derived fr1_rpy sequences (off), with plots:
#      runs repeat byte for byte, so the five runs of a cell use keypoint
#      budgets 0.93 ... 1.07 of the config's (a median over inputs, not one
#      draw);
#   4. conversion / export / render timings and the micro-benchmarks;
#   5. docs/benchmarks.md from scripts/benchmarks.md.in, every number generated.
#
# usage: scripts/regenerate-benchmarks.sh [--quick] [--clean]
#   --quick   1 run per mode, first 100 frames, short micro-benchmarks (a test
#             of the script: the page then says so at the top).
#   --clean   delete BUILD_DIR first (a build from scratch).
# environment: BUILD_DIR (default build), JOBS (default: nproc),
#   DYNSLAM_CACHE (default out/bench-cache: composite sequences),
#   BENCH_OUT (default out/bench: run folders and full reports),
#   DYNSLAM_SHARED_DIR (default ../shared).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
QUICK=0
CLEAN=0
for a in "$@"; do
  case "$a" in
    --quick) QUICK=1 ;;
    --clean) CLEAN=1 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "regenerate-benchmarks.sh: unknown argument '$a' (try --help)" >&2; exit 2 ;;
  esac
done

BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"
SHARED="${DYNSLAM_SHARED_DIR:-$ROOT/../shared}"
CACHE="${DYNSLAM_CACHE:-$ROOT/out/bench-cache}"
OUT="${BENCH_OUT:-$ROOT/out/bench}"
[ -d "$SHARED" ] || { echo "missing $SHARED (set DYNSLAM_SHARED_DIR)" >&2; exit 1; }
SHARED="$(cd "$SHARED" && pwd -P)"  # canonical, so the page can print it as ../shared
RPY="$SHARED/data/tum/rgbd_dataset_freiburg1_rpy"
WALKERS="$CACHE/rgbd_dataset_freiburg1_rpy_walkers"  # "freiburg1": fr1 intrinsics picked by name
DOC="$ROOT/docs/benchmarks.md"
IMAGES="$ROOT/docs/images/bench"
TEMPLATE="$ROOT/scripts/benchmarks.md.in"
START=$(date +%s)
LOAD_START="$(cut -d' ' -f1-3 /proc/loadavg)"

if [ "$QUICK" = 1 ]; then
  RUNS=1; STATIC_RUNS=1; LIMIT=(--max-frames 100); TOOL_RUNS=1; SPREAD=()
else
  RUNS=5; STATIC_RUNS=5; LIMIT=(); TOOL_RUNS=3; SPREAD=(--spread)
fi
say() { printf '\n== %s\n' "$*" >&2; }
[ -d "$RPY" ] || { echo "missing $RPY (set DYNSLAM_SHARED_DIR)" >&2; exit 1; }

# ---------------------------------------------------------------- 1. build
[ "$CLEAN" = 1 ] && rm -rf "$BUILD_DIR"
say "Release build in $BUILD_DIR ($JOBS jobs)"
cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
MICRO_TARGETS=($(sed -n 's/^dynslam_bench(\([A-Za-z0-9_]*\).*/bench_\1/p' apps/bench/CMakeLists.txt))
cmake --build "$BUILD_DIR" -j"$JOBS" --target dynslam
BUILT_MICRO=()
for t in "${MICRO_TARGETS[@]}"; do  # one broken micro-benchmark must not stop the page
  if cmake --build "$BUILD_DIR" -j"$JOBS" --target "$t"; then BUILT_MICRO+=("$t"); else echo "warning: $t did not build" >&2; fi
done
DYNSLAM="$BUILD_DIR/apps/dynslam"

# ------------------------------------------------------- 2. composite data
composite() {  # SCENARIO -> the composite folder, built once
  local dir="$CACHE/rgbd_dataset_freiburg1_$1"
  if [ ! -f "$dir/groundtruth.txt" ] || [ ! -d "$dir/masks" ]; then
    say "building the $1 composite into $dir"
    local PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3
    mkdir -p "$CACHE"
    rm -rf "$dir.tmp"
    "$PY" "$SHARED/tools/make_dynamic_sequence.py" "$SHARED/data/scenarios/$1.json" "$RPY" "$dir.tmp" >&2
    rm -rf "$dir"
    mv "$dir.tmp" "$dir"
  fi
}
composite rpy_walkers
composite rpy_close
composite rpy_panel
composite rpy_sitting
CLOSE="$CACHE/rgbd_dataset_freiburg1_rpy_close"
PANEL="$CACHE/rgbd_dataset_freiburg1_rpy_panel"
SITTING="$CACHE/rgbd_dataset_freiburg1_rpy_sitting"

# Issue 7 scenarios, made from fr1_rpy's lists (images linked, not copied):
# a 40-frame blackout in the middle (frames 330..369 removed), and the whole
# sequence played twice (second pass shifted by the sequence's time span, the
# groundtruth likewise).
derived_sequence() {  # NAME KIND
  local dir="$CACHE/$1"
  [ -f "$dir/groundtruth.txt" ] && return 0
  rm -rf "$dir"; mkdir -p "$dir"
  ln -s "$RPY/rgb" "$dir/rgb"; ln -s "$RPY/depth" "$dir/depth"
  if [ "$2" = gap ]; then
    # rgb.txt / depth.txt entries whose time falls in the 40 RGB frames 330..369
    local t0 t1
    t0=$(grep -v '^#' "$RPY/rgb.txt" | sed -n '331p' | cut -d' ' -f1)
    t1=$(grep -v '^#' "$RPY/rgb.txt" | sed -n '371p' | cut -d' ' -f1)
    for f in rgb.txt depth.txt; do
      grep -v '^#' "$RPY/$f" | awk -v a="$t0" -v b="$t1" '!($1 >= a - 0.01 && $1 < b - 0.01)' >"$dir/$f"
    done
    cp "$RPY/groundtruth.txt" "$dir/groundtruth.txt"
  else
    local shift
    shift=$(cat "$RPY/rgb.txt" "$RPY/depth.txt" "$RPY/groundtruth.txt" | grep -v '^#' |
            awk 'NR == 1 {lo = hi = $1} {if ($1 < lo) lo = $1; if ($1 > hi) hi = $1} END {printf "%.4f", hi - lo + 1}')
    for f in rgb.txt depth.txt groundtruth.txt; do
      { grep -v '^#' "$RPY/$f"
        grep -v '^#' "$RPY/$f" | awk -v s="$shift" '{t = $1; $1 = ""; printf "%.6f%s\n", t + s, $0}'
      } >"$dir/$f"
    done
  fi
}
GAP="$CACHE/rgbd_dataset_freiburg1_rpy_gap40"
TWICE="$CACHE/rgbd_dataset_freiburg1_rpy_twice"
derived_sequence rgbd_dataset_freiburg1_rpy_gap40 gap
derived_sequence rgbd_dataset_freiburg1_rpy_twice twice

# ---------------------------------------------------------------- 3. bench
rm -rf "$OUT"
mkdir -p "$OUT"
BENCH_CMDS=()
FAILED_BENCH=0
run_bench() {  # NAME SEQ MODES [RUNS]
  local cmd=("$DYNSLAM" bench "$2" -o "$OUT/$1" --modes "$3" --runs "${4:-$RUNS}" "${SPREAD[@]}" "${LIMIT[@]}" --plots)
  BENCH_CMDS+=("${cmd[*]}")
  say "${cmd[*]}"
  "${cmd[@]}" || FAILED_BENCH=1  # failures are listed in the report
  [ -f "$OUT/$1/report.md" ] || { echo "no report from $1" >&2; exit 1; }
}
run_bench fr1_rpy "$RPY" off,detect+flow "$STATIC_RUNS"
run_bench rpy_walkers "$WALKERS" off,detect,flow,detect+flow
run_bench rpy_close "$CLOSE" off,detect+flow
run_bench rpy_panel "$PANEL" off,detect+flow
run_bench rpy_sitting "$SITTING" off,detect+flow
run_bench fr1_rpy_gap40 "$GAP" off
run_bench fr1_rpy_twice "$TWICE" off

# ------------------------------------- 4. conversion, export, render timings
TOOLS_MD="$OUT/tools.md"
timed() {  # LABEL RUNS CMD... -> one table row, median wall and peak memory
  local label="$1" n="$2"; shift 2
  local walls=() mems=()
  for ((i = 1; i <= n; i++)); do
    /usr/bin/time -f "%e %M" -o "$OUT/time.txt" "$@" >"$OUT/tool.log" 2>&1 ||
      { echo "failed: $* (see $OUT/tool.log)" >&2; tail -5 "$OUT/tool.log" >&2; exit 1; }
    read -r w m <"$OUT/time.txt"
    walls+=("$w"); mems+=("$m")
  done
  local med_w med_m all
  med_w=$(printf '%s\n' "${walls[@]}" | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}')
  med_m=$(printf '%s\n' "${mems[@]}" | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}')
  all=$(printf '%s s, ' "${walls[@]}"); all="${all%, }"
  printf '| %s | `%s` | %s | **%s s** | %.0f MB |\n' "$label" "${*/#$ROOT\//}" "$all" "$med_w" "$(awk -v m="$med_m" 'BEGIN {print m / 1024}')" >>"$TOOLS_MD"
}
say "conversion, export and render timings"
{
  echo "| what | command | runs | median wall | peak memory |"
  echo "|---|---|---|---|---|"
} >"$TOOLS_MD"
mkdir -p "$OUT/tools"
CONVERT=("$DYNSLAM" convert -q "$RPY" "$OUT/tools/rpy.rawlog")
[ "$QUICK" = 1 ] && CONVERT+=(--max-frames 100)
timed "TUM → rawlog conversion of fr1_rpy" "$TOOL_RUNS" "${CONVERT[@]}"
EXPORT_RUN="$OUT/fr1_rpy/rgbd_dataset_freiburg1_rpy/off/run1"
timed "dense export of the fr1_rpy \`off\` run 1 (1 cm voxels, outlier removal)" "$TOOL_RUNS" \
  "$DYNSLAM" export "$EXPORT_RUN" -o "$OUT/tools/map.ply"
timed "render 1280x960 of that map (OSMesa, including loading the PLY)" "$TOOL_RUNS" \
  "$DYNSLAM" render "$OUT/tools/map.ply" -o "$OUT/tools/map.png" --view top

# -------------------------------------------------------- micro-benchmarks
MICRO_MD="$OUT/micro.md"
: >"$MICRO_MD"
micro_args() {  # NAME -> arguments (full / quick)
  case "$1:$QUICK" in
    orb_extractor:0) echo "$RPY 100" ;;      orb_extractor:1) echo "$RPY 20" ;;
    optim:0) echo "20 5" ;;                  optim:1) echo "5 2" ;;
    dynamic:0) echo "--runs 20 --pairs 40" ;; dynamic:1) echo "--runs 3 --pairs 5" ;;
    rawlog:0) echo "$RPY" ;;                 rawlog:1) echo "$RPY 50" ;;
    export:0) echo "$RPY 5 $OUT/bench_export" ;; export:1) echo "$RPY 25 $OUT/bench_export" ;;
    *) echo "" ;;
  esac
}
for target in "${MICRO_TARGETS[@]}"; do
  name="${target#bench_}"
  args=$(micro_args "$name")
  exe="$BUILD_DIR/apps/bench/$target"
  if [[ " ${BUILT_MICRO[*]} " != *" $target "* ]]; then
    printf '### %s\n\n(did not build)\n\n' "$target" >>"$MICRO_MD"
    continue
  fi
  say "$target $args"
  {
    printf '### %s\n\n```sh\n%s %s\n```\n\n```text\n' "$target" "${exe#$ROOT/}" "${args//$ROOT\//}"
    # shellcheck disable=SC2086
    if ! "$exe" $args 2>&1 | tr -d '\r'; then echo "(exit status non-zero)"; fi
    printf '```\n\n'
  } >>"$MICRO_MD"
done
sed -i "s#$ROOT/##g; s#$SHARED#../shared#g" "$MICRO_MD" "$TOOLS_MD"

# ---------------------------------------------------------- 5. the page
say "writing $DOC"
rm -rf "$IMAGES"
mkdir -p "$IMAGES"
REPORTS_MD="$OUT/reports.md"
: >"$REPORTS_MD"
for bench in fr1_rpy rpy_walkers rpy_close rpy_panel rpy_sitting fr1_rpy_gap40 fr1_rpy_twice; do
  (cd "$OUT/$bench" && find . -mindepth 3 -maxdepth 3 -name '*.png' -print0 | xargs -0 -I{} cp --parents {} "$IMAGES/")
  # Titles one level down, image links into docs/images/bench, paths relative.
  # From the first sequence heading on (the page explains the columns once).
  sed -n '/^## /,$p' "$OUT/$bench/report.md" | sed -e 's/^## /### /' \
      -e 's#](\([^)]*\.png\))#](images/bench/\1)#g' \
      -e "s#$ROOT/##g; s#$SHARED#../shared#g" \
      >>"$REPORTS_MD"
  echo >>"$REPORTS_MD"
done
[ "$FAILED_BENCH" = 1 ] && printf '\n**Some runs failed**: see the failure lists above.\n' >>"$REPORTS_MD"

END=$(date +%s)
MACHINE_MD="$OUT/machine.md"
{
  printf -- '- CPU: %s, %s cores available (`nproc`)\n' \
    "$(lscpu | sed -n 's/^Model name: *//p' | head -1)" "$(nproc)"
  printf -- '- Memory: %s total (`free -h`)\n' "$(free -h | awk '/^Mem:/ {print $2}')"
  printf -- '- OS: %s, kernel %s\n' "$(. /etc/os-release && echo "$PRETTY_NAME")" "$(uname -r)"
  printf -- '- Compiler: %s; Release build (`-O2 -mpopcnt`)\n' "$(c++ --version | head -1)"
  printf -- '- Libraries: OpenCV %s, MRPT %s, Eigen %s, PCL %s\n' \
    "$(pkg-config --modversion opencv4 2>/dev/null || echo '?')" \
    "$(dpkg-query -W -f '${Version}' libmrpt-dev 2>/dev/null | cut -d- -f1 || echo '?')" \
    "$(pkg-config --modversion eigen3 2>/dev/null || echo '?')" \
    "$(dpkg-query -W -f '${Version}' libpcl-dev 2>/dev/null | cut -d+ -f1 || echo '?')"
  printf -- '- Generated %s by `dynslam %s` (git %s%s) in %d min; load average %s at the start, %s at the end\n' \
    "$(date -u '+%Y-%m-%d %H:%M UTC')" "$("$DYNSLAM" --version | awk '{print $2}')" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo '?')" \
    "$(git diff --quiet HEAD 2>/dev/null || echo ', with local changes')" \
    $(((END - START + 59) / 60)) "$LOAD_START" "$(cut -d' ' -f1-3 /proc/loadavg)"
  if [ "$QUICK" = 1 ]; then
    printf -- '- **Quick mode** (`--quick`): 1 run per mode, first 100 frames only. These are not the published numbers.\n'
  fi
} >"$MACHINE_MD"

COMMAND_TXT="$OUT/command.txt"
{
  echo "scripts/regenerate-benchmarks.sh $*" | sed 's/ *$//'
  echo "# which runs:"
  for c in "${BENCH_CMDS[@]}"; do
    echo "$c" | sed "s#$ROOT/##g; s#$SHARED#../shared#g"
  done
} >"$COMMAND_TXT"

TMP_DOC="$DOC.tmp"
while IFS= read -r line || [ -n "$line" ]; do
  case "$line" in
    @COMMAND@) cat "$COMMAND_TXT" ;;
    @MACHINE@) cat "$MACHINE_MD" ;;
    @REPORTS@) cat "$REPORTS_MD" ;;
    @TOOLS@) cat "$TOOLS_MD" ;;
    @MICRO@) cat "$MICRO_MD" ;;
    *) printf '%s\n' "$line" ;;
  esac
done <"$TEMPLATE" >"$TMP_DOC"
mv "$TMP_DOC" "$DOC"
say "done in $(((END - START + 59) / 60)) min: $DOC, $IMAGES/ (full reports: $OUT/*/report.{md,json})"
