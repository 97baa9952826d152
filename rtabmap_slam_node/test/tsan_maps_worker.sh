#!/usr/bin/env bash
# The maps worker's gtest (MapsWorker_test.cpp) under ThreadSanitizer. Its code is ROS-free, so
# it builds against the core's TSan library (tools/build/sanitizers.sh tsan <dir> library):
#   rtabmap_slam_node/test/tsan_maps_worker.sh [build-dir (default build/tsan)]
# Any report fails the run (halt_on_error, as make test-tsan).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build/tsan}"
"$root/tools/build/sanitizers.sh" tsan "$build" library
flags="$(cat "$build/sanitizer-flags")"
out="$build/slam_node"
mkdir -p "$out"
launcher=(); command -v ccache >/dev/null && launcher=(ccache)
objects=()
for src in lib/MapsAssembler.cpp lib/MapsWorker.cpp lib/MapsHandover.cpp test/MapsWorker_test.cpp; do
  obj="$out/$(basename "$src" .cpp).o"
  "${launcher[@]}" "${SAN_CXX:-clang++}" -std=c++17 $flags -Wall -Wextra -c "$root/rtabmap_slam_node/$src" -o "$obj" \
    -I"$root/rtabmap_slam_node/include" -I"$root/rtabmap_core/include" -isystem /usr/include/eigen3 \
    -isystem /usr/include/opencv4
  objects+=("$obj")
done
"${SAN_CXX:-clang++}" -fsanitize=thread "${objects[@]}" -o "$out/test_maps_worker_tsan" -L"$build/lib" \
  -Wl,-rpath,"$build/lib" -lrtabmap_core -lgtest -lgtest_main -lopencv_core -pthread
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/tools/build/sanitizers/tsan.supp"
"$out/test_maps_worker_tsan" --gtest_repeat="${REPEAT:-3}"
