#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) in <build>/fuzz and runs each for a bounded time.
#   fuzz.sh <build-dir> [ros-include-dir]
# FUZZ_SECONDS (default 60) per target; FUZZ_TARGETS="g2o carmen" runs only those.
# Seeds: fuzz/corpus/<target>/ (small hand-made inputs) plus the head of the real datasets in
# ../shared/data (skipped with a message when absent) and a generated database. New inputs the
# fuzzer finds stay in <build>/fuzz/corpus/<target>/ (kept across runs, never in the repo).
# A crash, a hang (-timeout), an out-of-memory or a sanitizer report leaves its input in
# <build>/fuzz/artifacts/<target>/ and fails the run: fix the parser, then copy the input to
# fuzz/regressions/<target>/ so `make test` replays it for ever.
set -euo pipefail
build="$1"; ros_include="${2:-}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
data="$(cd "$root/.." && pwd)/shared/data"
seconds="${FUZZ_SECONDS:-60}"
jobs="${JOBS:-2}"
out="$build/fuzz"

# 1. The core with ASan + UBSan + coverage: the same build as `make test-asan` (library only).
"$root/tools/build/sanitizers.sh" asan "$build/asan" library
flags="$(cat "$build/asan/sanitizer-flags")"
# 2. The targets.
cmake -S "$root/fuzz" -B "$out" -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="$flags" -DRTABMAP_FUZZ_CORE_BUILD="$build/asan" \
  -DRTABMAP_FUZZ_ROS_INCLUDE="$ros_include" >/dev/null
cmake --build "$out" -- -j"$jobs"

# 3. Seed corpora.
corpus="$out/corpus"; artifacts="$out/artifacts"
mkdir -p "$corpus" "$artifacts"
seed() {  # seed <target> <name>: stdin -> the target's corpus
  mkdir -p "$corpus/$1"; cat > "$corpus/$1/$2"
}
for dir in "$root"/fuzz/corpus/*/; do
  t="$(basename "$dir")"; mkdir -p "$corpus/$t"; cp -f "$dir"* "$corpus/$t/" 2>/dev/null || true
done
mkdir -p "$corpus/database"
"$out/make_db_seed" "$corpus/database/seed.db" "$corpus/codec"
if [[ -d "$data" ]]; then
  # Heads of the real files: real syntax and values, small enough for many runs per second.
  for f in "$data"/posegraphs/*.g2o; do
    head -n 80 "$f" | seed g2o "$(basename "$f")"
    head -n 80 "$f" | seed trajectory "$(basename "$f")"
  done
  head -n 40 "$data/kitti00_velodyne/poses_00_camera_frame.csv" | seed trajectory kitti_poses.txt
  # (head closes the pipe early: bzcat's SIGPIPE is expected, not a failure.)
  for f in "$data"/radish/*.clf.bz2; do
    { bzcat "$f" || true; } | head -n 120 | seed carmen "$(basename "$f" .bz2)"
  done
  images=("$data"/rgbd_7scenes/frame-00000[01].color.jpg "$data"/rgbd_7scenes/frame-00000[01].depth.png)
  for f in "${images[@]}"; do [[ -f "$f" ]] && seed codec "$(basename "$f")" < "$f"; done
else
  echo "fuzz: no $data: seeding with fuzz/corpus only"
fi

# 4. Runs. TMPDIR: the path-based parsers read their input from a scratch file there.
export TMPDIR="${TMPDIR:-/tmp}"; [[ -d /dev/shm && -w /dev/shm ]] && export TMPDIR=/dev/shm
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/tools/build/sanitizers/ubsan.supp"
targets="${FUZZ_TARGETS:-$(cd "$out" && ls fuzz_* | sed 's/^fuzz_//' | tr '\n' ' ')}"
failed=()
for t in $targets; do
  [[ -x "$out/fuzz_$t" ]] || { echo "fuzz: no target $t (ROS targets need the catkin devel space)"; continue; }
  mkdir -p "$corpus/$t" "$artifacts/$t"
  case "$t" in database|codec|ros_*) max_len=65536 ;; *) max_len=8192 ;; esac
  echo "=== fuzz_$t: $seconds s"
  if ! "$out/fuzz_$t" "$corpus/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len="$max_len" -artifact_prefix="$artifacts/$t/" -print_final_stats=1 \
       > "$out/$t.log" 2>&1; then
    failed+=("$t")
    grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$out/$t.log" | head -n 8 || true
  fi
  grep -E "stat::number_of_executed_units|cov: " "$out/$t.log" | tail -n 2 | tr '\n' ' '; echo
done
if (( ${#failed[@]} )); then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $artifacts, logs in $out/<target>.log)"
  exit 1
fi
echo "fuzz: every target ran $seconds s clean"
