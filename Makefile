# joshuac: `make run` runs the demo robot, `make test` runs every test (`make test-fast` the unit tier). They set the machine up first.
SHELL := /bin/bash
export UV_PYTHON_DOWNLOADS := never
export PATH := $(HOME)/.local/bin:$(PATH)
VENV := .venv/bin
ROBOTS := $(basename $(notdir $(wildcard config/robots/*.pbtxt)))
RUN_CONFIG ?= config/robots/so100_sim.pbtxt
DURATION ?=
STATUS_INTERVAL ?=
PYTEST_ARGS ?=
# pytest-xdist workers of `make test`: three for every two cores, since the suite waits on timeouts, links and
# processes a quarter of the time (with three on two cores they kept 1.5 cores busy); 0: the tests run in
# pytest's own process
TEST_WORKERS ?= $(shell echo $$(( ($$(nproc) * 3 + 1) / 2 )))

.PHONY: setup install uninstall run test test-fast generate proto bench check cpp demo-train docs image api-types

setup:
	@bash scripts/setup.sh

## install: set up, then put joshuac and every joshua-* command on PATH for new shells
## (wrappers in BINDIR, default ~/.local/bin, running this checkout's .venv; see scripts/install.sh).
install: setup
	@bash scripts/install.sh install

uninstall:
	@bash scripts/install.sh uninstall

## run: build the demo description into a temporary directory and run it (Ctrl-C stops it;
## DURATION=10 makes it stop by itself; STATUS_INTERVAL=2 logs every node's state every 2 s).
## Nodes preferring CPP run the binaries setup built in build/bin.
run: setup
	$(VENV)/joshuac run $(RUN_CONFIG) --set "cpp_bin_dir=$(CURDIR)/build/bin" \
		$(if $(DURATION),--duration $(DURATION)) $(if $(STATUS_INTERVAL),--status-interval $(STATUS_INTERVAL))

## demo-train: scripted demonstrations in simulation -> a small ACT -> the registry -> the simulated arm driven
## by it through a generated supervisor (scripts/demo_train.py). Outputs go to DEMO_DIR (new or empty; default
## a fresh out/demo-train/<UTC time>); the registry is DEMO_DIR/registry unless JOSHUA_MODEL_REGISTRY is set.
## DEMO_SECONDS: how long the policy drives the simulated arm, counted from its first command.
DEMO_DIR ?= out/demo-train/$(shell date -u +%Y%m%dT%H%M%SZ)
DEMO_EPISODES ?= 10
DEMO_STEPS ?= 200
DEMO_EVAL_EPISODES ?= 10
DEMO_SECONDS ?= 20
demo-train: setup
	$(VENV)/python scripts/demo_train.py --output "$(DEMO_DIR)" --episodes $(DEMO_EPISODES) --steps $(DEMO_STEPS) \
		--eval-episodes $(DEMO_EVAL_EPISODES) --seconds $(DEMO_SECONDS)

## image: the container image of CONFIG (default the demo robot), tagged localhost/joshua/<robot>:<stamp hash>
## and :latest in podman's (else docker's) own storage; BASE=IMAGE another base, SET="KEY=VALUE ..." overrides,
## ENGINE=docker, CONTEXT=DIR for the build context (default build/image/<description>/). See docs/containers.md.
CONFIG ?= $(RUN_CONFIG)
BASE ?=
SET ?=
ENGINE ?=
CONTEXT ?=
image: setup
	$(VENV)/python scripts/image.py $(CONFIG) $(if $(BASE),--base $(BASE)) $(if $(ENGINE),--engine $(ENGINE)) \
		$(if $(CONTEXT),--context $(CONTEXT)) $(foreach override,$(SET),--set $(override))

## test: every test, in parallel workers; tests that must not overlap share an xdist_group (testsupport/tiers.py).
## None needs the machine to itself: simulated computers, their SSH rollouts and bag playback timing run beside the rest.
test: setup
	$(VENV)/pytest -n $(TEST_WORKERS) --dist loadgroup $(PYTEST_ARGS)

## test-fast: the unit tier alone (compiler, rules, drivers against in-process emulators): no processes, no ROS;
## in as many workers as `make test` (its tests wait too: 28 CPU-s in 62 s in one process).
test-fast: setup
	$(VENV)/pytest -n $(TEST_WORKERS) --dist loadgroup -m unit $(PYTEST_ARGS)

## generate: rebuild generated/<robot>/ for every description in config/robots/ (git keeps what it held).
generate: setup
	@for robot in $(ROBOTS); do \
		rm -rf generated/$$robot && $(VENV)/joshuac build config/robots/$$robot.pbtxt -o generated/$$robot || exit 1; \
	done

## docs: render the node-type table of docs/description-language.md from the node-type registry (tests fail when it is stale).
docs: setup
	$(VENV)/python -m joshua_codegen.readme_tables

## api-types: render web/src/types.ts from the dashboard's API schema (runtime/joshua_runtime/dashboard/api.schema.json);
## tests/test_dashboard_api.py fails when it is stale, and set-up refuses to build the page from stale types.
api-types: setup
	$(VENV)/python -m joshua_runtime.dashboard.api_typescript

## cpp: build the C++ node binaries into build/bin/ (a no-op when they are up to date; setup runs it).
cpp:
	@$(MAKE) --no-print-directory -C cpp

## proto: regenerate joshua_codegen/schema/*_pb2.py from proto/.
proto: setup
	PATH=$(VENV):$$PATH bash scripts/gen_proto.sh

check: setup
	$(VENV)/joshuac check config/robots/*.pbtxt

bench: setup
	@for script in bench/*.py; do echo "== $$script"; $(VENV)/python $$script || exit 1; done
