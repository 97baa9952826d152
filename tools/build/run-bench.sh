#!/usr/bin/env bash
# Runs every benchmark: the executables build/bin/bench-* (each prints its figures and a final
# JSON line), then the ROS-level benches tools/bench/*_bench.py (nodes end to end on bags, rviz
# under Xvfb) in the catkin workspace's environment. Benchmarks are long: they are never part
# of `make test`.
set -euo pipefail
bin="$1"
root="$(cd "$(dirname "$0")/../.." && pwd)"
ws="$(dirname "$bin")/ws"
shopt -s nullglob
benches=("$bin"/bench-*)
if [[ ${#benches[@]} -eq 0 ]]; then
  echo "no benchmarks built" >&2; exit 1
fi
for b in "${benches[@]}"; do
  echo "=== $(basename "$b")"
  "$b"
done
for py in "$root"/tools/bench/*_bench.py; do
  echo "=== $(basename "$py" .py)"
  (set +u; source "$ws/devel/setup.bash"; /usr/bin/python3 "$py")
done
