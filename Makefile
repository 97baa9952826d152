# rtabmap_ros: the two commands a user needs, and the ones developers use.
#   make demo    build, then run the demo (see README)
#   make test    build, then every test; last line "N passed, N failed, N skipped"
#   make build   install missing Debian packages, build the catkin workspace under build/
#   make bench   build, then the benchmarks and the sanitizer runs (long; never part of make test)
#   make clean   remove build/
#   make fuzz       libFuzzer targets of every parser of outside data, FUZZ_SECONDS (60) each
#   make test-asan  the core's unit tests built with AddressSanitizer + UBSan (build/asan)
#   make test-tsan  the core's unit tests built with ThreadSanitizer (build/tsan)
#   make test-draws the suites on synthetic scenes over DRAWS (20) other random draws of the scenes
#   make soak    build, then hours of the simulator's robot through ROS (SOAK_ARGS, see tools/soak/run_soak.py)
SHELL := /bin/bash
.SHELLFLAGS := -eo pipefail -c
.DEFAULT_GOAL := build
.PHONY: build deps configure test demo bench clean fuzz test-asan test-tsan test-draws soak

ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
BUILD := $(ROOT)/build
WS := $(BUILD)/ws
JOBS ?= 2
# Debian's catkin needs the system python (the pyenv python3 on PATH lacks catkin_pkg).
export PATH := /usr/bin:/bin:$(PATH)
export ROS_HOME := $(BUILD)/ros_home
export ROS_LOG_DIR := $(BUILD)/ros_home/log
# Looked up when the configure recipe runs (recursive `=`), after deps has installed ccache on a
# fresh machine; `:=` looked before, so a first build there ran without it and left it empty.
CCACHE = $(shell command -v ccache 2>/dev/null)
# Paths relative to the clone in ccache's keys: every clone of the repo shares one cache.
export CCACHE_BASEDIR := $(ROOT)
CMAKE_ARGS = -DCMAKE_BUILD_TYPE=Release \
  -DCATKIN_DEVEL_PREFIX=$(WS)/devel -DCMAKE_INSTALL_PREFIX=$(WS)/install \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
  $(if $(CCACHE),-DCMAKE_CXX_COMPILER_LAUNCHER=$(CCACHE) -DCMAKE_C_COMPILER_LAUNCHER=$(CCACHE))
IN_WS := source $(WS)/devel/setup.bash &&

deps:
	@$(ROOT)/tools/build/install-deps.sh

# A catkin workspace under build/ whose source space links this repository. The source space is
# the hidden build/ws/.src: roslaunch finds scripts by walking the package folder following
# symlinks and prunes only dot-folders, so a visible link back to the repo would loop forever.
SRC := $(WS)/.src
$(SRC)/CMakeLists.txt:
	mkdir -p $(SRC)
	ln -sfn ../../.. $(SRC)/rtabmap_ros
	ln -sfn /usr/share/catkin/cmake/toplevel.cmake $(SRC)/CMakeLists.txt

configure: deps $(SRC)/CMakeLists.txt
	@if [ ! -f $(WS)/build/CMakeCache.txt ]; then \
	  cmake -S $(SRC) -B $(WS)/build $(CMAKE_ARGS); fi

build: configure
	cmake --build $(WS)/build -- -j$(JOBS)
	@mkdir -p $(BUILD)/bin
	@for f in $(WS)/devel/lib/rtabmap_ros/rtabmap-* $(WS)/devel/lib/rtabmap_ros/bench-*; do \
	  [ -x "$$f" ] && ln -sfn "$$f" $(BUILD)/bin/; done; true
	@echo "Built. Tools are in build/bin/; source build/ws/devel/setup.bash for roslaunch/rosrun."

test: build
	@$(ROOT)/tools/build/run-tests.sh $(WS) $(JOBS)

DRAWS ?= 20
test-draws: build
	@$(ROOT)/tools/build/test-draws.sh $(WS)/build/rtabmap_ros/rtabmap_core/test $(DRAWS)

demo: build
	@$(IN_WS) $(ROOT)/tools/build/run-demo.sh $(WS) $(DEMO_ARGS)

# The sanitizer runs and the other draws of the synthetic scenes (issue 10) are too long for make
# test's budget: make bench runs them after the benchmarks (BENCH_SANITIZERS=0, BENCH_DRAWS=0
# skip them).
BENCH_SANITIZERS ?= 1
BENCH_DRAWS ?= 1
bench: build
	@$(ROOT)/tools/build/run-bench.sh $(BUILD)/bin
	@if [ "$(BENCH_DRAWS)" = 1 ]; then $(MAKE) --no-print-directory test-draws; fi
	@if [ "$(BENCH_SANITIZERS)" = 1 ]; then $(MAKE) --no-print-directory test-asan test-tsan; fi

soak: build
	@$(IN_WS) $(ROOT)/tools/build/run-soak.sh $(WS) $(SOAK_ARGS)

# Hardening (issue 10). The sanitizer builds are the core alone (plain CMake, clang); the ROS
# conversion fuzz targets only need the messages generated in the catkin workspace.
test-asan: deps
	@$(ROOT)/tools/build/sanitizers.sh asan $(BUILD)/asan

test-tsan: deps
	@$(ROOT)/tools/build/sanitizers.sh tsan $(BUILD)/tsan
	@$(ROOT)/rtabmap_slam_node/test/tsan_maps_worker.sh $(BUILD)/tsan

fuzz: configure
	cmake --build $(WS)/build --target rtabmap_ros_generate_messages_cpp -- -j$(JOBS)
	@$(ROOT)/tools/build/fuzz.sh $(BUILD) $(WS)/devel/include

clean:
	rm -rf $(BUILD)
