# The entry points named in the README. Each installs what it needs, builds with catkin, and fails loudly.
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS := $(ROOT)/catkin_ws
BUILD := $(WS)/build
BIN := $(WS)/devel/lib/art2part
EXAMPLE ?= $(ROOT)/examples/nist_ctc_01_asme1_rd.stp
OUT ?= $(ROOT)/out
JOBS ?= 2
# ROS from Debian runs on Debian's python3; a python3 of pyenv or a venv earlier on PATH lacks catkin_pkg and rospy.
export PATH := /usr/bin:/bin:$(PATH)
CATKIN := catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release

.PHONY: deps build install demo test bench clean

deps:
	@$(ROOT)/scripts/install-deps.sh

build: deps
	@$(ROOT)/scripts/link-workspace.sh
	@cd $(WS) && $(CATKIN) -j$(JOBS) > $(WS)/build.log 2>&1 \
	  || { tail -n 60 $(WS)/build.log; echo "make: catkin build failed (full log: $(WS)/build.log)"; exit 1; }
	@grep -E "warning:" $(WS)/build.log | grep -v "^/usr/" | sort -u | head -20 || true
	@echo "build: ok"

# The install space (catkin_ws/install): `source catkin_ws/install/setup.bash`, then roslaunch art2part cell.launch.
install: build
	@cd $(WS) && $(CATKIN) -j$(JOBS) install > $(WS)/build-install.log 2>&1 \
	  || { tail -n 60 $(WS)/build-install.log; echo "make: catkin install failed"; exit 1; }
	@echo "install: $(WS)/install (source $(WS)/install/setup.bash)"

# The main job on the bundled example part, headless: writes its results under out/.
demo: build
	@mkdir -p $(OUT)
	$(BIN)/art2part info $(EXAMPLE) | tee $(OUT)/part.txt
	$(BIN)/art2part info $(EXAMPLE) --json > $(OUT)/part.json
	$(BIN)/art2part render $(EXAMPLE) --out $(OUT)/part.png
	$(BIN)/art2part visibility $(EXAMPLE) --out $(OUT) --picture $(OUT)/cones.png | tee $(OUT)/visibility.txt
	$(BIN)/art2part plan $(EXAMPLE) --out $(OUT) | tee $(OUT)/plan.txt
	$(ROOT)/scripts/rviz_screenshot.sh $(OUT)/rviz_cell.png $(EXAMPLE)
	@echo "demo: results in $(OUT): part.txt part.json part.png, mesh.stl directions.csv visibility.bits cones.png," \
	  "plan.txt plan.json setups.png toolpaths.csv tools.json program.ngc (setup_<k>.ngc, tool.tbl, trajectory.csv)" \
	  "remaining.png, setup_<k>.png, setup_sheet.html, rviz_cell.png (the cell in rviz: part, setup frames, machine)"

# All tests: gtest per stage and rostest integration, through ctest (catkin_make run_tests exits 0 on failures),
# JOBS at a time: each rostest starts its own master on a free port; the tests that start LinuxCNC or launch the
# whole cell run alone (RUN_SERIAL in CMakeLists.txt).
test: build
	@cd $(WS) && $(CATKIN) -j$(JOBS) tests > $(WS)/build-tests.log 2>&1 \
	  || { tail -n 60 $(WS)/build-tests.log; echo "make: building the tests failed"; exit 1; }
	@cd $(BUILD) && ctest -j$(JOBS) --output-on-failure --timeout 600

bench: build
	@for b in $(BIN)/bench_*; do echo "== $$(basename $$b)"; $$b; done

clean:
	rm -rf $(WS)/build $(WS)/devel $(WS)/install $(OUT)
